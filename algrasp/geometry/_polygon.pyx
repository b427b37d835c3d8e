# cython: language_level=3, boundscheck=False, wraparound=False, cdivision=True, initializedcheck=False
"""Typed loops for a polygon's validity and hull (:mod:`algrasp.geometry.part`,
:mod:`algrasp.geometry.hull`), deciding exactly as their Python and GEOS references do.

Orientation signs are taken only where Shewchuk's error bound (widened to 1e-12) proves
them, and hull_order's hypot-scaled left-turn test only where libm's products clear the
limit by 1e-9 relative; otherwise the kernel is unsure (simple_ring: ask GEOS) or asks
Python's math.hypot itself. Built with -ffp-contract=off (no FMA). Re-exported by
:mod:`algrasp.geometry._geometry` (one GEOMETRY in :mod:`algrasp.compiled`);
``tests/algrasp/geometry/test_geometry_kernels.py`` compares the paths. O(n²) for the
ring test, O(n log n) for the hull.
"""

import math

from libc.math cimport atan2, fabs, isfinite, sqrt
from libc.stdlib cimport free, malloc, qsort

from algrasp._floats cimport _mod

from algrasp.geometry.angles import TWO_PI as _TWO_PI_PY
from algrasp.geometry.tolerances import ROUNDING as _ROUNDING_PY

cdef double TWO_PI = _TWO_PI_PY
cdef double PI = math.pi
cdef double ROUNDING = _ROUNDING_PY
cdef double HYPOT_SLACK = 1e-9  # relative: far above the few ulps between libm's sqrt(x² + y²) products and CPython's hypot's
cdef double HYPOT_FLOOR = 1e-100  # above it a square is a normal number: sqrt(dx² + dy²) is within 3 ulp
cdef double ORIENT_SLACK = 1e-12  # relative; Shewchuk's bound for orient2d in doubles is (3 + 16ε)ε
cdef double ORIENT_FLOOR = 1e-200  # below it the products may have lost digits to underflow: unsure
cdef object _hypot = math.hypot


cdef inline int _orient(double ax, double ay, double bx, double by, double cx, double cy) noexcept nogil:
    """The sign of the turn a → b → c where its double evaluation proves it (the error bound
    of Shewchuk's orient2d, with a wide margin); 0 when unsure."""
    cdef double left = (bx - ax) * (cy - ay), right = (by - ay) * (cx - ax)
    cdef double det = left - right, bound = ORIENT_SLACK * (fabs(left) + fabs(right))
    if fabs(det) <= ORIENT_FLOOR:
        return 0
    return 1 if det > bound else (-1 if det < -bound else 0)


cdef inline bint _apart(const double* x, const double* y, Py_ssize_t i, Py_ssize_t j, Py_ssize_t n) noexcept nogil:
    """Edges i and j (i → i + 1, cyclic) provably apart: one edge's ends strictly on one side of the other's line."""
    cdef Py_ssize_t i1 = (i + 1) % n, j1 = (j + 1) % n
    cdef int a = _orient(x[i], y[i], x[i1], y[i1], x[j], y[j])
    if a != 0 and a == _orient(x[i], y[i], x[i1], y[i1], x[j1], y[j1]):
        return True
    a = _orient(x[j], y[j], x[j1], y[j1], x[i], y[i])
    return a != 0 and a == _orient(x[j], y[j], x[j1], y[j1], x[i1], y[i1])


def simple_ring(list points):
    """Whether the closed polygon through ``points`` ([x, y] each) is provably simple: no
    edge of zero length, consecutive edges not collinear, other edges apart (sign-certain
    orientations only). Then GEOS finds it valid; False means unsure (ask GEOS). O(n²)."""
    cdef Py_ssize_t n = len(points), i, j
    cdef double* x = <double*> malloc(2 * n * sizeof(double))
    cdef double* y = x + n
    if n < 3:
        free(x)
        return False
    try:
        for i in range(n):
            x[i], y[i] = points[i][0], points[i][1]
        for i in range(n):
            j = (i + 1) % n
            if (x[i] == x[j] and y[i] == y[j]) or _orient(x[i - 1 if i else n - 1], y[i - 1 if i else n - 1],
                                                          x[i], y[i], x[j], y[j]) == 0:
                return False
        for i in range(n):
            for j in range(i + 2, n - 1 if i == 0 else n):
                if not _apart(x, y, i, j, n):
                    return False
        return True
    finally:
        free(x)


cdef struct Key:
    double x
    double y
    Py_ssize_t i


cdef int _by_xy(const void* a, const void* b) noexcept nogil:
    """By x, then y, then index: Python's stable sort of [x, y] keys (−0.0 equal to 0.0)."""
    cdef const Key* p = <const Key*> a
    cdef const Key* q = <const Key*> b
    if p.x != q.x:
        return -1 if p.x < q.x else 1
    if p.y != q.y:
        return -1 if p.y < q.y else 1
    return (p.i > q.i) - (p.i < q.i)


cdef bint _left_turn(const Key* a, const Key* b, const Key* c) except -1:
    """hull_order's test, cross > ROUNDING · hypot(b − a) · hypot(c − a) as Python computes it:
    decided here where libm's products clear the limit by HYPOT_SLACK, else by math.hypot."""
    cdef double dx1 = b.x - a.x, dy1 = b.y - a.y, dx2 = c.x - a.x, dy2 = c.y - a.y
    cdef double cross = dx1 * dy2 - dy1 * dx2
    cdef double h1 = sqrt(dx1 * dx1 + dy1 * dy1), h2 = sqrt(dx2 * dx2 + dy2 * dy2)
    cdef double t = ROUNDING * (h1 * h2)
    if h1 > HYPOT_FLOOR and h2 > HYPOT_FLOOR and isfinite(t):
        if cross > t * (1.0 + HYPOT_SLACK):
            return True
        if cross < t * (1.0 - HYPOT_SLACK):
            return False
    return bool(cross > ROUNDING * (_hypot(dx1, dy1) * _hypot(dx2, dy2)))


cdef Py_ssize_t _chain(const Key* keys, Py_ssize_t n, Py_ssize_t step, Py_ssize_t* out) except -1:
    """One monotone chain over ``keys`` in order (step 1) or reversed (−1) into ``out``; its length without the last."""
    cdef Py_ssize_t k = 0, j, i
    for j in range(n):
        i = j if step > 0 else n - 1 - j
        while k >= 2 and not _left_turn(&keys[out[k - 2]], &keys[out[k - 1]], &keys[i]):
            k -= 1
        out[k] = i
        k += 1
    return k - 1


def hull_order(list points):
    """:func:`algrasp.geometry.hull.hull_order` of ``points`` ([x, y] each): the same list. O(N log N)."""
    cdef Py_ssize_t n = len(points), i, a, b
    cdef Key* keys = <Key*> malloc((n + 1) * sizeof(Key))
    cdef Py_ssize_t* out = <Py_ssize_t*> malloc((2 * n + 2) * sizeof(Py_ssize_t))
    try:
        for i in range(n):
            keys[i].x, keys[i].y, keys[i].i = points[i][0], points[i][1], i
        qsort(keys, n, sizeof(Key), _by_xy)
        a = _chain(keys, n, 1, out)
        b = _chain(keys, n, -1, out + a)
        return [keys[out[i]].i for i in range(a + b)]
    finally:
        free(keys)
        free(out)


cdef inline double _nonneg(double v) noexcept nogil:
    """Python's max(v, 0.0): v unless 0.0 > v (−0.0 and NaN stay)."""
    return 0.0 if 0.0 > v else v


def corner_ranges(list corners, double sliver):
    """:func:`algrasp.geometry.hull._corner_ranges`: each corner kept (with its first normal)
    whose normal range, from the edge before it to its own edge, is wider than ``sliver``,
    and the last kept range's end. The same floats. O(h)."""
    cdef Py_ssize_t h = len(corners), k
    cdef double a, b, level, last, psi, before
    cdef double* psis = <double*> malloc((h + 1) * sizeof(double))
    kept = []
    try:
        for k in range(h):
            p, q = corners[k], corners[(k + 1) % h]
            psis[k] = atan2(<double> p[0] - <double> q[0], <double> q[1] - <double> p[1])
        level = last = psis[h - 1]
        for k in range(h):
            psi, before = psis[k], psis[k - 1 if k else h - 1]
            a = level + _nonneg(_mod(before - level + PI, TWO_PI) - PI)  # the corner
            b = a + _nonneg(_mod(psi - a + PI, TWO_PI) - PI)
            if b - a > sliver:
                kept.append((corners[k], a))
                last = b
            a = b + _nonneg(_mod(psi - b + PI, TWO_PI) - PI)  # its edge
            level = a + _nonneg(_mod(psi - a + PI, TWO_PI) - PI)
        return kept, last
    finally:
        free(psis)
