"""Named numerical tolerances: the one documented place for them.

Every tolerance is passed explicitly (``tol: Tolerances = DEFAULT_TOLERANCES``);
no bare epsilon appears elsewhere in the package. Lengths are relative to the
part's size (the diagonal of its bounding box) unless the name says otherwise.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Tolerances:
    """Tolerances used by parsing, geometry and the transfer functions.

    ``_rel`` values are relative to the part's size (the diagonal of its bounding box)
    unless their entry says otherwise; ``_rad`` values are radians. :data:`DEFAULT_TOLERANCES`
    holds the defaults.

    Parameters
    ----------
    closure_rel : float
        Largest gap between consecutive segments, relative to part size (conventions §5: 1e-6).
    position_rel : float
        A part smaller than this times its distance from the origin is refused (its
        analysis would be rounding noise: 1e-7 leaves 9 digits).
    zero_length_rel : float
        A segment shorter than this (relative) is zero-length.
    zero_area_rel : float
        A region whose area is below this times size² has zero area.
    concentric_rel : float
        Two centres closer than this (relative) coincide; decides regions of constant
        diameter/radius between circular arcs and vertices.
    angle_rad : float
        Two orientations closer than this are the same (breakpoints, merging steps,
        symmetry checks of structure).
    value_rel : float
        Relative tolerance on function values (symmetry of values).
    root_grid_rad : float
        Largest spacing of the sign-change grid used to isolate critical points on curved
        pieces (two extrema closer than this could merge).
    hull_sample_turn_rad : float
        Largest turn of the tangent between hull samples of a curve piece before exact refinement.
    sliver_rad : float
        Hull features and monotone runs narrower than this are rounding slivers (e.g. a
        curve cut a hair from its end) and are absorbed by their neighbours; far below any
        mechanically meaningful angle.
    circle_fit_rel : float
        A rational Bezier whose points lie this close (relative) to one circle *is* that
        circle's arc (rounding of written control points).
    arc_approximation_rel : float
        A polynomial Bezier within this (relative to the radius) of a circle approximates
        an arc (a cubic 90° arc is 2.7e-4 off).
    tessellation_turn_rad : float
        Polygon vertices turning at most this much (12°), in runs of at least
        ``tessellation_min_run``, are a tessellated curve (64-gon: 5.6°).
    tessellation_min_run : int
        The shortest run of vertices read as a tessellation (3).
    snap_turn_rad : float
        Polygon vertices turning at most this much (7.5°; all the same way, in runs of at
        least ``tessellation_min_run``, on one circle) tessellate an arc and become it in
        the robust model (a 48-gon turns 7.5°, a 64-gon 5.6°).
    symmetry_value_rel : float
        Values of d or r that agree within this (relative to size), plus the drawing's own
        value error, are equal when judging symmetry.

    Examples
    --------
    >>> DEFAULT_TOLERANCES.closure_rel, DEFAULT_TOLERANCES.tessellation_min_run
    (1e-06, 3)
    >>> Tolerances(closure_rel=1e-4).closure_rel, Tolerances() == DEFAULT_TOLERANCES
    (0.0001, True)
    """

    closure_rel: float = 1e-6
    position_rel: float = 1e-7
    zero_length_rel: float = 1e-9
    zero_area_rel: float = 1e-9
    concentric_rel: float = 1e-9
    angle_rad: float = 1e-9
    value_rel: float = 1e-9
    root_grid_rad: float = 0.004
    hull_sample_turn_rad: float = 0.05
    sliver_rad: float = 1e-7
    circle_fit_rel: float = 1e-9
    arc_approximation_rel: float = 1e-3
    tessellation_turn_rad: float = 0.2094395102393195  # 12°
    tessellation_min_run: int = 3
    snap_turn_rad: float = 0.1308996938995747  # 7.5°
    symmetry_value_rel: float = 1e-7


DEFAULT_TOLERANCES = Tolerances()


# Floating-point guards: not tolerances a user would tune but the limits of double
# arithmetic, named so that every comparison says which one it makes.
ROUNDING = 1e-12
"""Relative rounding of double arithmetic on values of order one (angles in radians,
curve parameters in [0, 1], lengths relative to the part's size): closer is equal."""
ROUNDING_FINE = 1e-15
"""A root-finding step (radians or curve parameter) below this is rounding: stop."""
EPS_REL = 4e-16
"""Two units of double rounding, relative (2⁻⁵¹ ≈ 4.4e-16, rounded down)."""
PARAM_END = 1e-9
"""Curve parameters (in [0, 1]) this close to an end are that end."""
PROBE_RAD = 1e-7
"""A probe this far (radians) beside a breakpoint samples the piece on that side."""
TINY = 1e-300
"""Guards divisions by a size that may be zero."""
LENGTH_REL = 1e-9
"""Distances (and curvature × size) below this, relative to the part's size, are zero."""
COEFF_NOISE = 1e-13
"""Polynomial coefficients (normalised to the largest) below this are rounding noise."""
DISCRIMINANT_REL = 1e-14
"""A quadratic's discriminant above −this × its terms is zero (a double root)."""
IMAG_REL = 1e-7
"""An eigenvalue whose imaginary part is below this (relative) is a real root."""
PLANNING_RAD = 1e-13
"""Algorithm A′ compares interval ends (radians, lifted) to this: rounding, not margin."""
SYMMETRY_TOL_RAD = 1e-7
"""Tolerance on breakpoints and images when testing F(θ + T) = F(θ) + T: root finding
places curved breakpoints to ~1e-12 rad, far inside this."""
HULL_TURN_RAD = 1e-7
"""The hull's edge normals must turn a full circle to within this (a sanity check)."""
TIME_ROUNDING_S = 1e-12
"""Simulated times (seconds) this close are the same instant (a control knot, a step)."""

UNCERTAINTY_FLOOR_RAD = 0.0017453292519943296  # 0.1°
"""No robust plan claims less than this (radians): the resolution at which the Drake
simulation reproduces rest orientations (its median error on exact polygons with matched
physics was 0.1°), so a claim below it could not be checked."""
MAX_UNCERTAINTY_RAD = 0.08726646259971647  # 5°
"""A robust plan whose part may end more than this from its final orientation (radians)
does not orient the part: it is refused with the limits under which a plan exists."""
DRAWING_SNAP_REL = 1e-6
"""Two points of a re-read drawing this close, relative to its extent, coincide (a fence's
root on its rail, a tail on its fence's tip): CAD programs re-save coordinates rounded."""
