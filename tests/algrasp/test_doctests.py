"""The runnable examples in the docstrings (they must stay true): the robust model, the
public API, the request guard and the settings' quantities."""

from __future__ import annotations

import doctest

import pytest

from algrasp import api
from algrasp.geometry import angles, arcforms, recognise, units
from algrasp.io import jsonguard
from algrasp.planning import cells, documents, physics, sampled, setvalued
from service import settings

MODULES = [recognise, arcforms, angles, units, documents, sampled, api, jsonguard, settings, physics, cells, setvalued]


@pytest.mark.parametrize("module", MODULES, ids=lambda m: m.__name__)
def test_docstring_examples(module: object) -> None:
    result = doctest.testmod(module, raise_on_error=False)  # type: ignore[arg-type]
    assert result.attempted > 0 and result.failed == 0
