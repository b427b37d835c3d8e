"""Bounds on what a request may hold, checked before any work (issue 18).

JSON as clients send it is not always JSON: Python's ``json.dumps`` writes ``NaN`` and
``Infinity``, numbers may overflow a float (``1e400``) or have thousands of digits, a
string may hold a lone surrogate (``"\\ud800"``) that no UTF-8 encoder accepts, and
nesting can be deep enough to exhaust a recursive parser or pickler. :func:`parse_json`
turns each of these into a :class:`~algrasp.errors.LimitExceededError` or
:class:`~algrasp.errors.PartDocumentError` naming the JSON path, so the service answers
422 and nothing downstream (records, workers, caches) ever sees such a value.

Complexity: one ``json.loads`` plus one iterative walk, O(size of the document).
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from typing import Any

from algrasp.errors import LimitExceededError, PartDocumentError


@dataclass(frozen=True)
class JsonBounds:
    """Attributes:
        max_depth: deepest nesting of arrays/objects (a part document needs 5).
        max_string_chars: longest string (names, keys, layer names).
        max_int_digits: most digits of an integer literal (a float's range is 309).
        max_nodes: most values in one document (an 8 MB body of numbers is ~1 M).
    """

    max_depth: int = 32
    max_string_chars: int = 100_000
    max_int_digits: int = 20
    max_nodes: int = 2_000_000


DEFAULT_BOUNDS = JsonBounds()


class _RefusedError(Exception):
    def __init__(self, problem: str) -> None:
        super().__init__(problem)
        self.problem = problem


def _constant(name: str) -> Any:
    raise _RefusedError(f"{name} is not a number JSON allows: send finite numbers only")


def _int(bounds: JsonBounds) -> Any:
    def parse(text: str) -> int:
        if len(text.lstrip("-")) > bounds.max_int_digits:
            raise _RefusedError(f"an integer of {len(text)} digits (at most {bounds.max_int_digits})")
        return int(text)

    return parse


def _float(text: str) -> float:
    value = float(text)
    if not math.isfinite(value):
        raise _RefusedError(f"{text[:40]} overflows a double: send finite numbers only")
    return value


def parse_json(data: bytes | str, field: str = "body", bounds: JsonBounds = DEFAULT_BOUNDS) -> Any:
    """Parse and bound-check a JSON document.

    Raises PartDocumentError (``field``: where) for invalid JSON, non-finite numbers or
    lone surrogates, LimitExceededError for depth/size limits.

    >>> parse_json(b'{"a": [1, 2.5]}')
    {'a': [1, 2.5]}
    >>> parse_json(b'{"a": NaN}')
    Traceback (most recent call last):
    ...
    algrasp.errors.PartDocumentError: body: NaN is not a number JSON allows: send finite numbers only
    """
    try:
        text = data.decode("utf-8") if isinstance(data, bytes) else data
        value = json.loads(text, parse_constant=_constant, parse_int=_int(bounds), parse_float=_float)
    except _RefusedError as exc:
        raise PartDocumentError(field, exc.problem) from None
    except UnicodeDecodeError:
        raise PartDocumentError(field, "not UTF-8 text") from None
    except json.JSONDecodeError as exc:
        raise PartDocumentError(field, f"not valid JSON: {exc.msg} at line {exc.lineno} column {exc.colno}") from None
    except RecursionError:
        raise LimitExceededError(field, f"nested deeper than {bounds.max_depth} levels") from None
    check_value(value, field, bounds)
    return value


def check_value(value: Any, field: str = "body", bounds: JsonBounds = DEFAULT_BOUNDS) -> None:
    """Walk a parsed JSON value (iteratively: no recursion limit to hit) and refuse deep
    nesting, huge strings, lone surrogates, non-finite floats and too many nodes."""
    stack: list[tuple[Any, str, int]] = [(value, field, 0)]
    nodes = 0
    while stack:
        v, path, depth = stack.pop()
        nodes += 1
        if nodes > bounds.max_nodes:
            raise LimitExceededError(field, f"more than {bounds.max_nodes} values")
        if isinstance(v, dict):
            if depth >= bounds.max_depth:
                raise LimitExceededError(path, f"nested deeper than {bounds.max_depth} levels")
            for k, x in v.items():
                _check_string(k, f"{path} (a key)", bounds)
                stack.append((x, f"{path}.{k}", depth + 1))
        elif isinstance(v, list):
            if depth >= bounds.max_depth:
                raise LimitExceededError(path, f"nested deeper than {bounds.max_depth} levels")
            stack.extend((x, f"{path}[{i}]", depth + 1) for i, x in enumerate(v))
        elif isinstance(v, str):
            _check_string(v, path, bounds)
        elif isinstance(v, float) and not math.isfinite(v):
            raise PartDocumentError(path, "not a finite number")


def _check_string(s: str, path: str, bounds: JsonBounds) -> None:
    if len(s) > bounds.max_string_chars:
        raise LimitExceededError(path[:200], f"a string of {len(s)} characters (at most {bounds.max_string_chars})")
    try:
        s.encode("utf-8")
    except UnicodeEncodeError:
        raise PartDocumentError(path[:200].encode("utf-8", "replace").decode(), "a lone surrogate (\\ud800–\\udfff) "
                                "is not text: send valid Unicode") from None
