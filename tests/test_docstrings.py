"""Every public name (``algrasp.__all__``) has a numpydoc docstring: a summary, its
parameters (every one of a function's, by name) or attributes, what a function returns,
and examples. The examples themselves run as doctests (``--doctest-modules``).

A constant (``DEFAULT_PHYSICS``) is documented by its class; a dataclass documents each
of its fields, an error its typed fields, HTTP status and exit code."""

from __future__ import annotations

import dataclasses
import inspect
import warnings
from typing import Any

import pytest
from numpydoc.docscrape import ClassDoc, FunctionDoc, NumpyDocString

import algrasp
from algrasp.errors import AlgraspError


def _documented(obj: Any) -> Any:
    """What documents a public name: a function or class itself, a constant its class."""
    return obj if inspect.isfunction(obj) or inspect.isclass(obj) else type(obj)


def _parse(obj: Any) -> NumpyDocString:
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # an unknown or misspelled section is a failure, not a warning
        if inspect.isclass(obj):
            return ClassDoc(obj, config={"show_class_members": False})
        return FunctionDoc(obj)


def _names(section: list[Any]) -> set[str]:
    """The names a Parameters/Attributes section documents (``x, y : float`` is two)."""
    return {n.strip().lstrip("*") for p in section for n in p.name.split(",") if n.strip()}


def _signature_names(func: Any) -> list[str]:
    skip = (inspect.Parameter.VAR_POSITIONAL, inspect.Parameter.VAR_KEYWORD)
    return [p.name for p in inspect.signature(func).parameters.values() if p.kind not in skip and p.name != "self"]


def _problems(obj: Any) -> list[str]:
    doc = _parse(obj)
    out = []
    if not "".join(doc["Summary"]).strip():
        out.append("no summary")
    if not "".join(doc["Examples"]).strip():
        out.append("no Examples")
    elif ">>>" not in "\n".join(doc["Examples"]):
        out.append("Examples have no >>> line")
    if inspect.isclass(obj):
        documented = _names(doc["Parameters"]) | _names(doc["Attributes"])
        if not documented:
            out.append("neither Parameters nor Attributes")
        wanted = [f.name for f in dataclasses.fields(obj)] if dataclasses.is_dataclass(obj) else []
        if issubclass(obj, AlgraspError):
            wanted = [*obj.public_fields, "http_status", "exit_code"]
        out += [f"{name!r} not in Parameters/Attributes" for name in wanted if name not in documented]
        return out
    params = _signature_names(obj)
    if params and not doc["Parameters"]:
        out.append("no Parameters")
    if not doc["Returns"]:
        out.append("no Returns")
    out += [f"parameter {name!r} not in Parameters" for name in params if name not in _names(doc["Parameters"])]
    return out


@pytest.mark.parametrize("name", algrasp.__all__)
def test_public_name_has_a_numpydoc_docstring(name: str) -> None:
    problems = _problems(_documented(getattr(algrasp, name)))
    assert not problems, f"algrasp.{name}: {'; '.join(problems)}"


def _f(x: int, *args: Any, y: int = 0, **kwargs: Any) -> int:
    """Add.

    Parameters
    ----------
    x : int
        One.

    Returns
    -------
    int
    """
    return x + y


@dataclasses.dataclass
class _Thing:
    """A thing.

    Attributes
    ----------
    a, b : float
        Its sides (mm).

    Examples
    --------
    >>> _Thing(1.0, 2.0).a
    1.0
    """

    a: float
    b: float
    c: float = 0.0


def test_the_check_can_fail() -> None:
    assert _problems(_f) == ["no Examples", "parameter 'y' not in Parameters"]  # *args, **kwargs need no entry
    assert _problems(_Thing) == ["'c' not in Parameters/Attributes"]
    assert _problems(AlgraspError) == []
    with pytest.raises(Warning):
        _parse(type("Misspelt", (), {"__doc__": "Summary.\n\nExampels\n--------\n>>> 1\n1\n"}))
