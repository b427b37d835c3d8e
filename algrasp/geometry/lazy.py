"""A cached property without a lock, for the immutable value objects of the core.

:class:`functools.cached_property` takes an ``RLock`` on every first computation in
Python 3.11 (dropped in 3.12): ~0.4 µs of a ~0.2 µs descriptor call, paid by every fresh
hull, table and function of a part (dozens per robust analysis). This one computes the
value on first access and stores it in the instance's ``__dict__``, which then shadows the
descriptor (a non-data descriptor), exactly as functools' does. Two threads racing on a
first access may both compute it; the values here are pure functions of immutable
objects, so both store the same result.

>>> class Box:
...     def __init__(self, side: float) -> None:
...         self.side = side
...     @cached_property
...     def area(self) -> float:
...         "The side squared."
...         return self.side * self.side
>>> b = Box(3.0)
>>> b.area, b.__dict__["area"], Box.area.__doc__
(9.0, 9.0, 'The side squared.')
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Generic, TypeVar, overload

T = TypeVar("T")


class cached_property(Generic[T]):  # noqa: N801  (the name of the functools descriptor it replaces)
    """Compute once per instance, on first access; O(1) after."""

    def __init__(self, func: Callable[[Any], T]) -> None:
        self.func = func
        self.attrname = func.__name__
        self.__doc__ = func.__doc__

    def __set_name__(self, owner: type, name: str) -> None:
        self.attrname = name

    @overload
    def __get__(self, instance: None, owner: type | None = None) -> cached_property[T]: ...
    @overload
    def __get__(self, instance: object, owner: type | None = None) -> T: ...
    def __get__(self, instance: object | None, owner: type | None = None) -> T | cached_property[T]:
        if instance is None:
            return self
        value = self.func(instance)
        instance.__dict__[self.attrname] = value
        return value
