"""The runnable examples in the robust model's docstrings (they must stay true)."""

from __future__ import annotations

import doctest

import pytest

from algrasp import arcforms, recognise


@pytest.mark.parametrize("module", [recognise, arcforms], ids=lambda m: m.__name__)
def test_docstring_examples(module: object) -> None:
    result = doctest.testmod(module, raise_on_error=False)  # type: ignore[arg-type]
    assert result.attempted > 0 and result.failed == 0
