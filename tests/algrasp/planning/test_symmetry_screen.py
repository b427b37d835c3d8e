"""The extremum screen of the symmetry judgement (algrasp/planning/symmetry.py): trying
the lowest and highest extremum first, then the survivors at every tested extremum,
keeps exactly the orders a test of every order at every tested extremum keeps."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from algrasp.geometry.functions import SupportPairFunction
from algrasp.planning.analysis import EXACT, analyse_document
from algrasp.planning.symmetry import EXTREMA_TESTED, MAX_SYMMETRY_ORDER, _extremum_orders
from algrasp.testing import shapes

GEAR = Path(__file__).resolve().parents[3] / "algrasp" / "examples" / "real" / "gear-12.json"
PARTS: dict[str, Any] = {"triangle": shapes.regular_polygon(3), "hexagon": shapes.regular_polygon(6),
                         "random 7-gon": shapes.random_polygon(7, 3), "rectangle": shapes.rectangle(3.0, 1.0),
                         "blob": shapes.bezier_blob(6, 1), "gear": json.loads(GEAR.read_text())}


def _every_order(f: SupportPairFunction, tol: float) -> list[int]:
    """Each order k tested alone at the lowest and highest extrema (as the screen picks them)."""
    value = np.array([e.value for e in f.extrema])
    theta = np.array([e.theta for e in f.extrema])
    order = np.argsort(value, kind="stable")
    half = EXTREMA_TESTED // 2
    pick = order if len(order) <= EXTREMA_TESTED else np.concatenate([order[:half], order[-half:]])
    return [k for k in range(MAX_SYMMETRY_ORDER, 1, -1)
            if all(abs(float(f.values(np.array([theta[i] + f.period / k]))[0]) - value[i]) <= tol for i in pick)]


@pytest.mark.parametrize("name", PARTS)
@pytest.mark.parametrize("tol", [1e-9, 1e-4, 1e-2])
def test_screen_keeps_the_orders_of_a_full_test(name: str, tol: float) -> None:
    a = analyse_document(PARTS[name], EXACT)
    for f in (a.diameter, a.radius):
        assert _extremum_orders(f, tol).tolist() == _every_order(f, tol)
