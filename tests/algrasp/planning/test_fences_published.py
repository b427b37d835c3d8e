"""A published result on fence designs, reproduced (issue 36).

No figure of Berretty, Goldberg, Overmars & van der Stappen (1998) or of Peshkin &
Sanderson (1988) with numbers that could be checked (a part's coordinates with its fence
angles) was found: the search tool returns the paper's abstract only (README "Conveyor
fences" lists the queries). What is reproduced instead is the paper's theorem, labelled:

    Berretty et al. 1998, Comput. Geom. 10: any polygonal part can be oriented (up to
    symmetry) by a sequence of fences on a conveyor belt, in their model (frictionless
    fences, the part pushed by each as by a frictionless jaw, fences alternating sides).

Stated polygons: seeded random star-shaped polygons of 3 to 8 vertices (simple ones only)
and the test suite's named ones. With μ_f = 0 and the exact model the designer must find a
design for every one (a refusal fails the theorem here), and each design must bring 3,600
starts to its claimed orientations under the brute-force push of the tests (not the
planner's)."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from algrasp.errors import PartDocumentError
from algrasp.planning.analysis import EXACT, analyse_document
from algrasp.planning.fences import design_fences, fence_rules
from tests.algrasp.planning.test_fences import RECT, TRIANGLE, _admissible, _exact_part, _poly, _simulate, _worst_miss_deg

SEED = 1998
COUNT = 24


def _star_polygons() -> list[list[list[float]]]:
    """COUNT seeded star-shaped polygons (vertices at sorted random angles and radii)."""
    rng = np.random.default_rng(SEED)
    out = []
    while len(out) < COUNT:
        n = int(rng.integers(3, 9))
        t, r = np.sort(rng.uniform(0.0, 2 * np.pi, n)), rng.uniform(5.0, 20.0, n)
        out.append([[float(a * math.cos(b)), float(a * math.sin(b))] for a, b in zip(r, t)])
    return out


@pytest.mark.parametrize("vertices", [RECT, TRIANGLE, [[0, 0], [6, 0], [5, 2], [1, 3]], *_star_polygons()])
def test_every_polygon_has_a_frictionless_fence_design(vertices: list[list[float]]) -> None:
    try:
        analysis = analyse_document(_poly(vertices), EXACT)
    except PartDocumentError:  # a self-intersecting draw is no polygonal part
        pytest.skip("not a simple polygon")
    # the paper's model: a part keeps its orientation between fences (no turn over a tip)
    rules = replace(fence_rules([0.0, 0.0]), exit_steepness=None, exit_turns=False)
    design = design_fences(analysis, rules, min_margin_deg=0.0)
    _admissible(design, rules)
    assert _worst_miss_deg(_simulate(_exact_part(vertices), design.angles), design) < 0.01
