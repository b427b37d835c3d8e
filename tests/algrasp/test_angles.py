"""Degrees ↔ radians (algrasp.geometry.angles): what is written reads back exactly."""

from __future__ import annotations

import math

import mpmath
import numpy as np
from hypothesis import given
from hypothesis import strategies as st

from algrasp.geometry.angles import to_deg, to_rad

ANGLES_RAD = st.one_of(st.floats(-1e4, 1e4), st.floats(1e-12, 1e-3), st.floats(-1e-3, -1e-12))


@given(ANGLES_RAD)
def test_written_degrees_read_back_to_the_same_radians(r: float) -> None:
    """Law: to_deg ∘ to_rad is the identity on what to_deg writes (a document read back
    writes out unchanged). The plain product π/180 breaks it for 5 % of angles, e.g. a
    margin of 0.08726646259971638 rad written as 4.999999999999995° read back as …996°."""
    d = to_deg(r)
    assert to_deg(to_rad(d)) == d
    assert to_rad(d) * (180.0 / math.pi) == d


def test_the_margin_that_once_changed_on_reading() -> None:
    d = to_deg(0.08726646259971638)
    assert d == 4.999999999999995 and to_deg(to_rad(d)) == d


@given(st.lists(ANGLES_RAD, min_size=1, max_size=50))
def test_arrays_convert_like_numbers(rs: list[float]) -> None:
    d = to_deg(np.array(rs))
    back = to_rad(d)
    assert back.tolist() == [to_rad(float(x)) for x in d]
    assert np.array_equal(to_deg(back), d)


@given(st.floats(-1e6, 1e6))
def test_radians_are_within_an_ulp_of_the_exact_product(d: float) -> None:
    """Against 50-digit arithmetic: the chosen neighbour is never more than one ulp (plus
    the product's own half ulp) from d·π/180."""
    with mpmath.workdps(50):
        exact = mpmath.mpf(d) * mpmath.pi / 180
        err = abs(mpmath.mpf(to_rad(d)) - exact)
    assert err <= 1.5 * math.ulp(float(exact)) or err == 0
