# Set-up and main commands. Needs only Python 3.11 and make.
PYTHON ?= $(shell command -v python3.11 2>/dev/null || command -v python3)
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: run test lint bench clean

$(STAMP): pyproject.toml
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[dev,sim]'
	touch $(STAMP)

run: $(STAMP)
	$(BIN)/algrasp analyze algrasp/examples/pie-20.json
	$(BIN)/algrasp plan algrasp/examples/pie-20.json --action squeeze
	$(BIN)/algrasp plan algrasp/examples/pie-20.json --action push-grasp --figure logs/pie-20-push-grasp.svg

test: $(STAMP)
	$(BIN)/python -m pytest -q -n 2

lint: $(STAMP)
	$(BIN)/ruff check algrasp optimisation service tests benchmarks
	$(BIN)/mypy

bench: $(STAMP)
	$(BIN)/python benchmarks/bench_analysis.py
	$(BIN)/python benchmarks/bench_plan.py
	$(BIN)/python benchmarks/bench_optimise.py
	$(BIN)/python benchmarks/bench_validate.py
	$(BIN)/python benchmarks/bench_record.py

clean:
	rm -rf $(VENV) build *.egg-info
