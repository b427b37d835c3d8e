# Set-up and main commands. Needs only Python 3.11 and make.
PYTHON ?= $(shell command -v python3.11 2>/dev/null || command -v python3)
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: run test lint bench clean

# The compiled kernels are built at install (setup.py): a changed .pyx or .pxd re-installs.
$(STAMP): pyproject.toml setup.py $(wildcard algrasp/*.pxd algrasp/*/*.pyx algrasp/*/*.pxd)
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[all,dev]'
	touch $(STAMP)

# The service on embedded defaults (SQLite and records in logs/, a local worker pool):
# plans the bundled example part once, then serves and prints the docs URL.
run: $(STAMP)
	$(BIN)/algrasp serve --host 127.0.0.1 --port $(or $(PORT),8000)

test: $(STAMP)
	$(BIN)/python -m pytest -q -n 2

lint: $(STAMP)
	$(BIN)/ruff check algrasp optimisation service tests benchmarks
	$(BIN)/mypy

bench: $(STAMP)
	$(BIN)/python benchmarks/bench_analysis.py
	$(BIN)/python benchmarks/bench_robust.py
	$(BIN)/python benchmarks/bench_default_model.py
	$(BIN)/python benchmarks/bench_cold_start.py
	$(BIN)/python benchmarks/bench_scaling.py
	$(BIN)/python benchmarks/bench_import.py
	$(BIN)/python benchmarks/bench_plan.py
	$(BIN)/python benchmarks/bench_optimise.py
	$(BIN)/python benchmarks/bench_validate.py
	$(BIN)/python benchmarks/bench_record.py
	$(BIN)/python benchmarks/bench_service.py
	$(BIN)/python benchmarks/bench_batch.py
	$(BIN)/python benchmarks/bench_workbench.py
	$(BIN)/python benchmarks/bench_cli.py

clean:
	rm -rf $(VENV) build *.egg-info $(foreach k,_kernels _lookups _geometry _polygon,algrasp/*/$(k).c algrasp/*/$(k).*.so)
