# cython: language_level=3, boundscheck=False, wraparound=False, cdivision=True, initializedcheck=False
"""Typed loops for the diameter/radius analysis of point-like hulls
(:mod:`algrasp.geometry.functions`), support values of vertices (:mod:`algrasp.geometry.bank`)
and a polygon's dead-band terms (:mod:`algrasp.planning.deadband`), bit-identical to their
Python and numpy references (numpy's own calls, cos/sin/hypot, stay numpy calls).

Every value is made by the same IEEE operations in the same order as the Python path (no
FMA: built with -ffp-contract=off; Python's float remainder written out with its rule;
libm's atan2, sin and cos, which Python's math module calls). The one comparison whose
Python form is not libm's (``math.hypot(dx, dy) <= limit``: CPython's own hypot) is
decided here only where a bound proves it (|Δ| far above the limit) and otherwise by
Python's math.hypot itself. Used through :mod:`algrasp.compiled` only;
``tests/algrasp/geometry/test_geometry_kernels.py`` compares the two paths. Radians
throughout; O(c log c) for c cells.
"""

import math

import numpy as np

from libc.math cimport atan2, ceil, cos, fabs, floor, sin, sqrt, INFINITY
from libc.stdlib cimport free, malloc, qsort

from algrasp._floats cimport _bisect_right, _mod

from algrasp.geometry._polygon import corner_ranges, hull_order, simple_ring  # re-exported: one GEOMETRY
from algrasp.geometry.angles import TWO_PI as _TWO_PI_PY

cdef double TWO_PI = _TWO_PI_PY
cdef double PI = math.pi
cdef double HALF_PI = math.pi / 2
cdef double HYPOT_FLOOR = 1e-100  # above it |Δ|² is a normal number: sqrt(dx² + dy²) is within 3 ulp
cdef double ROUNDED_APART = 2e-9  # keys this far apart round to different multiples of 1e-9
cdef double BUCKET_SLACK = 1e-3  # in units of 1e-9: far above the rounding of a·1e9 (≲ 1e-6 for |a| < 1e3)
cdef object _hypot = math.hypot
cdef object _round = round
cdef object _empty = np.empty, _cos = np.cos, _sin = np.sin, _np_hypot = np.hypot


cdef struct RunC:
    double start
    double end
    int sign


cdef struct Cut:
    double psi
    Py_ssize_t k


cdef int _by_cut(const void* a, const void* b) noexcept nogil:
    """By ψ, then index: Python's stable sort of the indices by their cut."""
    cdef const Cut* p = <const Cut*> a
    cdef const Cut* q = <const Cut*> b
    if p.psi != q.psi:
        return -1 if p.psi < q.psi else 1
    return (p.k > q.k) - (p.k < q.k)


cdef Py_ssize_t _starts(const Cut* cuts, Py_ssize_t m, Py_ssize_t n, double angle_rad, double* ea, Py_ssize_t* en,
                        Py_ssize_t* ef) noexcept nogil:
    """Each cell's start and its near and far features, cuts closer than ``angle_rad`` one;
    the count. Before the first cut the features are the last cuts' of each term."""
    cdef Py_ssize_t i, k, e = 0, near = -1, far = 0
    cdef double prev = -INFINITY
    for i in range(m - 1, -1, -1):
        if cuts[i].k < n:
            far = cuts[i].k
            break
    for i in range(m - 1, -1, -1):
        if cuts[i].k >= n:
            near = cuts[i].k - n
            break
    for i in range(m):
        k = cuts[i].k
        if k < n:
            far = k
        else:
            near = k - n
        if cuts[i].psi - prev > angle_rad:
            ea[e] = cuts[i].psi
            e += 1
        en[e - 1], ef[e - 1] = near, far
        prev = cuts[i].psi
    return e


def cells(list bp, bint diameter, double angle_rad):
    """:func:`algrasp.geometry.functions._cells` from the breakpoint list ``bp``: the same
    tuple of (near, far, ψ_a, ψ_b); None when a breakpoint is NaN (the Python path then).
    O(n log n)."""
    cdef Py_ssize_t n = len(bp), m = 2 * n if diameter else n, i, e
    cdef double base, c
    cdef Cut* cuts = <Cut*> malloc((m + 1) * sizeof(Cut))
    cdef double* ea = <double*> malloc((m + 1) * sizeof(double))
    cdef Py_ssize_t* en = <Py_ssize_t*> malloc((2 * m + 2) * sizeof(Py_ssize_t))
    cdef Py_ssize_t* ef = en + m + 1
    try:
        for i in range(n):
            c = bp[i]
            if c != c:
                return None
            cuts[i].psi, cuts[i].k = c - PI, i
            if diameter:
                cuts[n + i].psi, cuts[n + i].k = c, n + i
        base = cuts[0].psi
        for i in range(m):
            cuts[i].psi = base + _mod(cuts[i].psi - base, TWO_PI)
        qsort(cuts, m, sizeof(Cut), _by_cut)
        e = _starts(cuts, m, n, angle_rad, ea, en, ef)
        out = []
        for i in range(e):
            c = ea[i + 1] if i + 1 < e else ea[0] + TWO_PI
            if c - ea[i] > angle_rad:
                out.append((en[i], ef[i], ea[i], c))
        return tuple(out)
    finally:
        free(cuts)
        free(ea)
        free(en)


cdef inline int _sign(double x) noexcept nogil:
    return (x > 0.0) - (x < 0.0)


cdef bint _concentric(double dx, double dy, double limit) except -1:
    """math.hypot(dx, dy) <= limit: false when a bound proves |Δ| > limit, else asked of Python."""
    cdef double s = sqrt(dx * dx + dy * dy)
    if s > 2.0 * limit and s > HYPOT_FLOOR:
        return False
    return bool(_hypot(dx, dy) <= limit)


cdef Py_ssize_t _cell_runs(double dx, double dy, double a, double b, double limit, double angle_rad,
                           RunC* out) except -1:
    """:func:`algrasp.geometry.functions._point_like_runs` into ``out`` (at most 4); the count."""
    cdef double phi, k0, x, y, m, sg
    cdef double edges[5]
    cdef Py_ssize_t n = 1, count = 0, i
    if _concentric(dx, dy, limit):
        out[0].start, out[0].end, out[0].sign = a, b, 0
        return 1
    phi = atan2(dy, dx)
    k0 = ceil((a - phi) / PI)
    edges[0] = a
    for i in range(3):  # a cell is at most a turn wide: these cover its roots
        x = phi + (k0 + i) * PI
        if a < x < b:
            edges[n] = x
            n += 1
    edges[n] = b
    for i in range(n):
        x, y = edges[i], edges[i + 1]
        m = 0.5 * (x + y)
        sg = -dx * sin(m) + dy * cos(m)
        if y - x > angle_rad:
            out[count].start, out[count].end, out[count].sign = x, y, _sign(sg)
            count += 1
    return count


cdef Py_ssize_t _merge(RunC* r, Py_ssize_t n, double sliver) noexcept nogil:
    """:func:`algrasp.geometry.functions._merge` in place; the count kept."""
    cdef Py_ssize_t k = 0, i
    for i in range(n):
        if k and r[i].end - r[i].start <= sliver:
            r[k - 1].end = r[i].end
            continue
        if k and r[k - 1].sign == r[i].sign:
            r[k - 1].end = r[i].end
        else:
            r[k] = r[i]
            k += 1
    if k > 1 and r[0].sign == r[k - 1].sign:
        r[k - 1].end = r[0].end + TWO_PI
        for i in range(k - 1):
            r[i] = r[i + 1]
        k -= 1
    return k


def point_runs(tuple cell_list, list centers, double limit, double angle_rad, double sliver, run):
    """:func:`algrasp.geometry.functions.theta_runs` of a hull whose features are all
    point-like: ``centers`` holds each feature's centre then the centre of mass (near
    index −1); ``run`` makes each θ-run. The same list of runs."""
    cdef Py_ssize_t nc = len(cell_list), nf = len(centers), total = 0, i, near, far
    cdef double fx, fy, gx, gy
    cdef RunC* runs = <RunC*> malloc((4 * nc + 1) * sizeof(RunC))
    try:
        for i in range(nc):
            cell = <tuple> cell_list[i]
            near, far = cell[0], cell[1]
            near, far = near + nf if near < 0 else near, far + nf if far < 0 else far
            if not (0 <= near < nf and 0 <= far < nf):
                raise IndexError(f"cell {i} names a feature not in centers")
            F, G = centers[near], centers[far]
            fx, fy, gx, gy = F[0], F[1], G[0], G[1]
            total += _cell_runs(fx - gx, fy - gy, cell[2], cell[3], limit, angle_rad, runs + total)
        total = _merge(runs, total, sliver)
        # θ = π/2 − ψ reverses the order and the sign of the derivative.
        return [run(HALF_PI - runs[i].end, HALF_PI - runs[i].start, -runs[i].sign) for i in range(total - 1, -1, -1)]
    finally:
        free(runs)


cdef bint _same_rounding(double a, double b) except -1:
    """round(a, 9) == round(b, 9), as Python has it: equal when a and b lie in the same
    half-open step of 1e-9 around a multiple of it, clear of its edges by far more than
    the rounding of a·1e9 (so without Python's decimal conversion); else asked of Python."""
    cdef double ta = a * 1e9, tb = b * 1e9, f = floor(ta + 0.5)
    if fabs(ta) < 1e12 and f - 0.5 + BUCKET_SLACK < ta < f + 0.5 - BUCKET_SLACK and \
            f - 0.5 + BUCKET_SLACK < tb < f + 0.5 - BUCKET_SLACK:
        return True
    return bool(_round(a, 9) == _round(b, 9))


def extremum_keys(list runs, double period, double angle_rad, list labels):
    """The extrema of :func:`algrasp.geometry.functions.analyse` before their values: each
    (start, θ wrapped into the period, label) once per key (θ rounded to 9 digits, the first
    kept), from ``labels[prev sign + 1][next sign + 1]`` (None: no extremum). Keys more
    than 2e-9 apart never round alike; closer ones are compared by :func:`_same_rounding`.
    O(n k) for k kept."""
    cdef Py_ssize_t n = len(runs), i, j, count = 0
    cdef int p, q
    cdef double start, x, key
    cdef double* kept = <double*> malloc((n + 1) * sizeof(double))
    out = []
    if not n:
        free(kept)
        raise IndexError("list index out of range")  # as the Python path's runs[-1]
    try:
        for i in range(n):
            p = (<tuple> runs[i - 1 if i else n - 1])[2]
            q = (<tuple> runs[i])[2]
            if not (-1 <= p <= 1 and -1 <= q <= 1):
                raise ValueError(f"run signs must be -1, 0 or 1, got {p} and {q}")
            label = labels[p + 1][q + 1]
            if label is None:
                continue
            start = (<tuple> runs[i])[0]
            x = _mod(start, period)
            key = 0.0 if period - x <= angle_rad else x
            for j in range(count):
                if not fabs(key - kept[j]) > ROUNDED_APART and _same_rounding(key, kept[j]):
                    break
            else:
                kept[count] = key
                count += 1
                out.append((start, key, label))
        return out
    finally:
        free(kept)


cdef double* _vertex_table(list bp, list centers) except NULL:
    """A table of vertices in one C buffer (3n): the breakpoints, then the centres' x, then
    their y; the caller frees it."""
    cdef Py_ssize_t n = len(bp), i
    cdef double* buf = <double*> malloc(3 * n * sizeof(double))
    if buf == NULL:
        raise MemoryError()
    for i in range(n):
        buf[i] = bp[i]
        buf[n + i], buf[2 * n + i] = centers[i][0], centers[i][1]
    return buf


def widest(list bp, list centers, list psi, list cos_psi, list sin_psi):
    """:func:`algrasp.planning.deadband.nominal_size` of a hull of vertices only (breakpoints
    ``bp``, vertex ``centers``): the largest ⟨c(ψ) − c(ψ + π), u(ψ)⟩ over the m normals ψ
    (``psi`` holds the m, then the m + π; ``cos_psi``, ``sin_psi`` numpy's cosines and
    sines of the first m), each support point found as FeatureTable.feature_index finds
    it. O(m log n)."""
    cdef Py_ssize_t n = len(bp), m = len(cos_psi), k, i, j
    cdef double base, x, v, best = -INFINITY
    cdef bint nan = False
    cdef double* buf = _vertex_table(bp, centers)
    cdef double* rest = buf
    cdef double* cx = buf + n
    cdef double* cy = buf + 2 * n
    try:
        base = rest[0]
        for k in range(m):
            x = psi[k]
            i = _bisect_right(rest + 1, n - 1, base + _mod(x - base, TWO_PI))
            x = psi[k + m]
            j = _bisect_right(rest + 1, n - 1, base + _mod(x - base, TWO_PI))
            v = (cx[i] - cx[j]) * <double> cos_psi[k] + (cy[i] - cy[j]) * <double> sin_psi[k]
            if v != v:
                nan = True
            elif v > best:
                best = v
        return float("nan") if nan else best
    finally:
        free(buf)


cdef object _vertex_support(list bp, list centers, const double[:] psi, bint pair):
    """h(ψ) as FeatureTable.support of FeatureTable.feature_index finds it for a table of
    vertices only (breakpoints ``bp``, vertex ``centers``): ψ lifted into the table's
    turn, its feature by bisection, then ⟨c, u(ψ)⟩ + 0.0 with numpy's cosines and sines of
    the lifted ψ. ``pair``: ψ is π/2 − θ and the normals are ψ then ψ + π (one array, as
    SupportPairFunction.values makes them), and the result is h(ψ) + h(ψ + π). O(m log n)."""
    cdef Py_ssize_t n = len(bp), m = psi.shape[0], total = 2 * m if pair else m, k, i, j
    cdef double base, p
    cdef double* buf = _vertex_table(bp, centers)
    cdef double* rest = buf
    cdef double* cx = buf + n
    cdef double* cy = buf + 2 * n
    cdef Py_ssize_t* idx = <Py_ssize_t*> malloc((total + 1) * sizeof(Py_ssize_t))
    x = _empty(total)
    out = _empty(m)
    cdef double[::1] xv = x, ov = out
    cdef const double[::1] cv, sv
    try:
        base = rest[0]
        for k in range(m):
            p = HALF_PI - psi[k] if pair else psi[k]
            xv[k] = base + _mod(p - base, TWO_PI)
            if pair:
                xv[k + m] = base + _mod(p + PI - base, TWO_PI)
        for k in range(total):
            idx[k] = _bisect_right(rest + 1, n - 1, xv[k])
        cv = _cos(x)
        sv = _sin(x)
        for k in range(m):
            i = idx[k]
            ov[k] = cx[i] * cv[k] + cy[i] * sv[k] + 0.0
            if pair:
                j = idx[k + m]
                ov[k] = ov[k] + (cx[j] * cv[k + m] + cy[j] * sv[k + m] + 0.0)
        return out
    finally:
        free(buf)
        free(idx)


def vertex_support(list bp, list centers, const double[:] psi):
    """FeatureTable.support of FeatureTable.feature_index for a table of vertices only: h(ψ) (m,)."""
    return _vertex_support(bp, centers, psi, False)


def width_values(list bp, list centers, const double[:] theta):
    """SupportPairFunction.values of a diameter function on a table of vertices only:
    h(ψ) + h(ψ + π) at ψ = π/2 − θ, the same array (m,)."""
    return _vertex_support(bp, centers, theta, True)


cdef double _pairwise(const double* a, Py_ssize_t n) noexcept nogil:
    """numpy's pairwise summation of a contiguous float64 run (its add.reduce inner loop):
    below 8 in order, up to 128 in eight interleaved partial sums, above that halves."""
    cdef Py_ssize_t i, j, n2
    cdef double res, r[8]
    if n < 8:
        res = 0.0
        for i in range(n):
            res += a[i]
        return res
    if n <= 128:
        for j in range(8):
            r[j] = a[j]
        i = 8
        while i < n - (n % 8):
            for j in range(8):
                r[j] += a[i + j]
            i += 8
        res = ((r[0] + r[1]) + (r[2] + r[3])) + ((r[4] + r[5]) + (r[6] + r[7]))
        while i < n:
            res += a[i]
            i += 1
        return res
    n2 = n // 2
    n2 -= n2 % 8
    return _pairwise(a, n2) + _pairwise(a + n2, n - n2)


def distance_integral(list vertices, tuple com, list nodes, list weights):
    """:func:`algrasp.planning.deadband._distance_integral` of a polygon's vertices about
    ``com``: ⅓ ∮ |p| (x dy − y dx) by the Gauss rule (``nodes``, ``weights`` on [0, 1]) on
    each edge, with numpy's hypot on the same (N, k, 2) array and numpy's summation order
    (:func:`_pairwise`, from +0.0). The same float. O(N k)."""
    cdef Py_ssize_t n = len(vertices), k = len(nodes), i, j
    cdef double cx = com[0], cy = com[1], x0, y0, dx, dy
    cdef double* t = <double*> malloc(2 * k * sizeof(double))
    cdef double* w = t + k
    cdef double* pts = <double*> malloc((2 * n + 2) * sizeof(double))
    cdef double* prod = <double*> malloc((n * k + 1) * sizeof(double))
    p = _empty((n, k, 2))
    cdef double[:, :, ::1] pv = p
    cdef const double[:, ::1] rho
    try:
        for j in range(k):
            t[j], w[j] = nodes[j], weights[j]
        for i in range(n):
            pts[2 * i], pts[2 * i + 1] = <double> vertices[i][0] - cx, <double> vertices[i][1] - cy
        for i in range(n):
            for j in range(k):
                x0, y0 = pts[2 * i], pts[2 * i + 1]
                dx, dy = pts[2 * ((i + 1) % n)] - x0, pts[2 * ((i + 1) % n) + 1] - y0
                pv[i, j, 0] = x0 + dx * t[j]
                pv[i, j, 1] = y0 + dy * t[j]
        rho = _np_hypot(p[..., 0], p[..., 1])
        for i in range(n):
            dx, dy = pts[2 * ((i + 1) % n)] - pts[2 * i], pts[2 * ((i + 1) % n) + 1] - pts[2 * i + 1]
            for j in range(k):
                prod[i * k + j] = rho[i, j] * (pv[i, j, 0] * dy - pv[i, j, 1] * dx) * w[j]
        return (0.0 + _pairwise(prod, n * k)) / 3.0
    finally:
        free(t)
        free(pts)
        free(prod)
