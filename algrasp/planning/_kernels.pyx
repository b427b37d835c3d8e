# cython: language_level=3, boundscheck=False, wraparound=False, cdivision=True, initializedcheck=False
"""Typed loops for the set-valued classification (:mod:`algrasp.planning.setvalued`,
:mod:`algrasp.planning.setcells`), bit-identical to their numpy reference.

Every value is made by the same IEEE operations in the same order as the numpy path
(no FMA: built with -ffp-contract=off; numpy's remainder, maximum and minimum written
out with its rules; libm sin/cos, which numpy's match on this platform). Used through
:mod:`algrasp.compiled` only, and only where the numpy path is the reference:
``tests/test_kernels.py`` compares the two. Radians throughout; O(n log n) for n nodes.
"""

import numpy as np

from libc.math cimport ceil, cos, fabs, floor, isfinite, isnan, sin, INFINITY, NAN
from cpython.tuple cimport PyTuple_GET_ITEM
from libc.stdlib cimport calloc, free, malloc

from algrasp._floats cimport _add_distinct, _bisect_left, _bisect_right, _insertion_sort, _max, _min, _mod

from algrasp.planning._lookups import (fixed, images, keys, lifted, lookup, pointwise, rest_zones, shifted,
                                      sink_widths, steps_floats, widest)  # re-exported: one KERNELS

cdef double ROUNDING = 0.0, TWO_PI = 0.0, EDGE_RAD = 0.0, INSIDE = 0.0, SLOPE_NOISE = 0.0, GRID_RAD = 0.0
cdef double HALF_PI = np.pi / 2, PI = np.pi
cdef bint _ready = False
cdef object _NONE = None


cdef void _init() except *:
    """The constants of the numpy path, read from it once (it imports this module lazily)."""
    global ROUNDING, TWO_PI, EDGE_RAD, INSIDE, SLOPE_NOISE, GRID_RAD, _ready, _NONE
    from algrasp.geometry.angles import TWO_PI as two_pi
    from algrasp.geometry.tolerances import ROUNDING as rounding
    from algrasp.planning import setvalued as sv
    ROUNDING, TWO_PI, EDGE_RAD, INSIDE, SLOPE_NOISE = rounding, two_pi, sv.EDGE_RAD, sv._INSIDE, sv.SLOPE_NOISE
    GRID_RAD = sv.GRID_RAD
    _NONE = sv._NONE
    _ready = True


cdef struct Pair:
    double v
    Py_ssize_t i


cdef int _sort_pairs(Pair* a, Py_ssize_t n) except -1:
    """Sort a[0:n] by value, stably (numpy's stable argsort of values filled in index
    order; no NaN here): insertion-sorted runs of 16, merged bottom-up."""
    cdef Py_ssize_t i, j, w, lo, mid, hi, p, q, t
    cdef Pair v
    cdef Pair* tmp
    for lo in range(0, n, 16):
        hi = lo + 16 if lo + 16 < n else n
        for i in range(lo + 1, hi):
            v = a[i]
            j = i - 1
            while j >= lo and v.v < a[j].v:
                a[j + 1] = a[j]
                j -= 1
            a[j + 1] = v
    if n <= 16:
        return 0
    tmp = <Pair*>malloc(n * sizeof(Pair))
    if tmp == NULL:
        raise MemoryError()
    w = 16
    while w < n:
        for lo in range(0, n - w, 2 * w):
            mid, hi = lo + w, (lo + 2 * w if lo + 2 * w < n else n)
            p, q, t = lo, mid, lo
            while p < mid and q < hi:
                if a[q].v < a[p].v:
                    tmp[t] = a[q]
                    q += 1
                else:
                    tmp[t] = a[p]
                    p += 1
                t += 1
            while p < mid:
                tmp[t] = a[p]
                p += 1
                t += 1
            for i in range(lo, t):
                a[i] = tmp[i]
        w *= 2
    free(tmp)
    return 0


cdef class _Buf:
    """Scratch doubles freed with their owner."""
    cdef double* p

    def __cinit__(self, Py_ssize_t n):
        self.p = <double*>malloc(max(n, 1) * sizeof(double))
        if self.p == NULL:
            raise MemoryError()

    def __dealloc__(self):
        free(self.p)


# ------------------------------------------------------------------ nodes (_nodes)

cdef Py_ssize_t _nodes(const double* grid, Py_ssize_t ng, const double* edges, Py_ssize_t ne, const double* kinks,
                       Py_ssize_t nk, double T, double* x, char* kink) except -1:
    """setvalued._nodes into x, kink (room for every raw node); returns the node count."""
    cdef Py_ssize_t N = 1 + ng + 2 * ne + nk, i, n = 0
    cdef Pair* raw = <Pair*>malloc(N * sizeof(Pair))
    cdef char fl
    if raw == NULL:
        raise MemoryError()
    raw[0].v, raw[0].i = _mod(0.0, T), 0
    for i in range(ng):
        raw[1 + i].v, raw[1 + i].i = _mod(grid[i], T), 1 + i
    for i in range(ne):
        raw[1 + ng + i].v, raw[1 + ng + i].i = _mod(edges[i] - EDGE_RAD, T), 1 + ng + i
        raw[1 + ng + ne + i].v, raw[1 + ng + ne + i].i = _mod(edges[i] + EDGE_RAD, T), 1 + ng + ne + i
    for i in range(nk):
        raw[1 + ng + 2 * ne + i].v, raw[1 + ng + 2 * ne + i].i = _mod(kinks[i], T), 1 + ng + 2 * ne + i
    try:
        _sort_pairs(raw, N)
    except MemoryError:
        free(raw)
        raise
    for i in range(N):
        fl = raw[i].i >= 1 + ng
        if i == 0 or raw[i].v - raw[i - 1].v > ROUNDING:
            x[n], kink[n] = raw[i].v, fl
            n += 1
        elif fl:
            kink[n - 1] = 1
    if T - raw[N - 1].v <= ROUNDING and n > 1:  # the last group is node 0's
        if kink[n - 1]:
            kink[0] = 1
        n -= 1
    free(raw)
    return n


# ------------------------------------------------------------- slopes (edges.slopes)

cdef object _support(object f, double* psi, Py_ssize_t m, double* px, double* py):
    """hull.support_points at psi[0:m] into px, py (points and arcs here; a table with
    curve features through the numpy path, on the same batch)."""
    table = f.hull.table
    cdef const double[:] bp = table.breakpoints
    cdef const double[:, :] centres = table.centers
    cdef const double[:] radii = table.radii
    cdef double base = bp[0], xl, c
    cdef Py_ssize_t F = bp.shape[0], i, lo, hi, mid, k
    cdef bint vertices = table.vertices_only
    cdef double[:, :] pts
    if len(table.s0):
        arr = np.empty(m)
        for i in range(m):
            arr[i] = psi[i]
        pts = np.asarray(f.hull.support_points(arr), dtype=float)
        for i in range(m):
            px[i], py[i] = pts[i, 0], pts[i, 1]
        return None
    for i in range(m):
        xl = base + _mod(psi[i] - base, TWO_PI)
        lo, hi = 0, F - 1  # searchsorted(breakpoints[1:], xl, side="right")
        while lo < hi:
            mid = (lo + hi) >> 1
            if bp[1 + mid] <= xl:
                lo = mid + 1
            else:
                hi = mid
        k = lo
        if vertices:
            px[i], py[i] = centres[k, 0], centres[k, 1]
        else:
            px[i] = centres[k, 0] + radii[k] * cos(xl)  # at ψ lifted into the table's turn
            py[i] = centres[k, 1] + radii[k] * sin(xl)
    return None


cdef object _slopes(object f, const double* theta, Py_ssize_t m, double* g, double* v):
    """edges.slopes: f′ and f at theta[0:m]."""
    cdef _Buf b = _Buf(7 * m)
    cdef double* psi = b.p
    cdef double* q = b.p + m  # 2m normals: ψ then ψ + π (a diameter's both ends)
    cdef double* px = b.p + 3 * m
    cdef double* py = b.p + 5 * m
    cdef double cx, cy, c, s, chx, chy
    cdef Py_ssize_t i
    cdef bint diameter = f.kind == "diameter"
    for i in range(m):
        psi[i] = HALF_PI - theta[i]
    if diameter:  # one batch [ψ, ψ + π], as the numpy path asks
        for i in range(m):
            q[i], q[m + i] = psi[i], psi[i] + PI
        _support(f, q, 2 * m, px, py)
    else:
        com = np.asarray(f.com, dtype=float)
        cx, cy = float(com[0]), float(com[1])
        for i in range(m):
            q[i] = psi[i] + PI
        _support(f, q, m, px, py)
    for i in range(m):
        if diameter:
            chx, chy = px[i] - px[m + i], py[i] - py[m + i]
        else:
            chx, chy = cx - px[i], cy - py[i]
        c, s = cos(psi[i]), sin(psi[i])
        g[i] = chx * s - chy * c
        v[i] = chx * c + chy * s
    return None


# ---------------------------------------------------------------- barriers (basins)

cdef list _basins(const double* vals, Py_ssize_t m, double depth, char* mask):
    """barriers.basins and basin_cells: marks the cells of every basin shallower than
    ``depth`` (below its lower rim) in mask[0:m]; returns the rims in order."""
    cdef list rims = []
    cdef Py_ssize_t i, k, E = 0, cnt = 0, lo, hi, t, stop
    cdef double d, flo, fhi, rim
    cdef int prev
    if depth <= 0.0:
        return rims
    cdef Py_ssize_t* nz = <Py_ssize_t*>malloc(2 * m * sizeof(Py_ssize_t))
    cdef int* sg = <int*>malloc(2 * m * sizeof(int))
    if nz == NULL or sg == NULL:
        free(nz)
        free(sg)
        raise MemoryError()
    cdef Py_ssize_t* idx = nz + m
    cdef int* kinds = sg + m
    try:
        for i in range(m):
            d = vals[(i + 1) % m] - vals[i]
            if d > 0.0 or d < 0.0:
                nz[cnt], sg[cnt] = i, (1 if d > 0.0 else -1)
                cnt += 1
        if cnt < 2:
            return rims
        for k in range(cnt):
            prev = sg[k - 1] if k > 0 else sg[cnt - 1]
            if sg[k] != prev:  # an extremum at nz[k]: +1 a minimum, −1 a maximum
                idx[E], kinds[E] = nz[k], sg[k]
                E += 1
        if E < 2:
            return rims
        for k in range(E):
            if kinds[k] <= 0:
                continue
            lo, hi = (k - 1 if k > 0 else E - 1), (k + 1) % E
            flo, fhi = vals[idx[lo]], vals[idx[hi]]
            rim = fhi if fhi < flo else flo  # Python's min(f[lo], f[hi])
            if rim - vals[idx[k]] < depth:
                stop = idx[hi] + (m if idx[hi] < idx[lo] else 0) + 1
                for t in range(idx[lo], stop):
                    if vals[t % m] <= rim:
                        mask[t % m] = 1
                rims.append(rim)
        return rims
    finally:
        free(nz)
        free(sg)


cdef void _barriers(const double* x, Py_ssize_t n, Py_ssize_t K, double T, const double* rows,
                    const double* cl, double stall, double eps, double* out_r, double* out_l) except *:
    """barriers.barrier_sets for one level ``cl`` (K, n) on rows (2K, 2n) from _rows:
    the farthest right and left barrier of each cell over the copies. O(K·n log n)."""
    cdef Py_ssize_t k, i, j, m = 2 * n
    cdef double r, lf
    cdef Py_ssize_t* idx = <Py_ssize_t*>malloc((m + 2 * n) * sizeof(Py_ssize_t))
    cdef double* lv = <double*>malloc(2 * n * sizeof(double))
    if idx == NULL or lv == NULL:
        free(idx)
        free(lv)
        raise MemoryError()
    cdef Py_ssize_t* jr = idx + m
    cdef Py_ssize_t* jl = jr + n
    for k in range(K):
        for i in range(n):  # rightward from each cell's end, leftward from its start (lifted)
            lv[i] = cl[k * n + i] + stall * (x[i + 1] if i < n - 1 else T) + 2.0 * eps
            lv[n + i] = cl[((k + 1) % K) * n + i] - stall * (x[i] + T) + 2.0 * eps
        _reaching(rows + k * m, m, lv, n, True, idx, jr)
        _reaching(rows + (K + k) * m, m, lv + n, n, False, idx, jl)
        for i in range(n):
            j = jr[i]
            r = INFINITY if j == m else (x[j] + 0.0 if j < n else x[j - n] + T)
            j = m - 1 - jl[i]  # mirrored index jl is node m − 1 − jl
            lf = -INFINITY if jl[i] == m else (x[j] + 0.0 if j < n else x[j - n] + T) - T
            out_r[i] = r if k == 0 else _max(out_r[i], r)
            out_l[i] = lf if k == 0 else _min(out_l[i], lf)
    free(idx)
    free(lv)


def barriers(x, double T, node_values, cell_max, double stall, double eps):
    """barriers.barriers through :func:`_rows` and :func:`_barriers` (the classification's
    own search): the right and left barrier of each cell, the same floats."""
    cdef const double[::1] xv = np.ascontiguousarray(x, dtype=float)
    cdef const double[:, ::1] nv = np.ascontiguousarray(node_values, dtype=float)
    cdef const double[:, ::1] cl = np.ascontiguousarray(cell_max, dtype=float)
    cdef Py_ssize_t K = nv.shape[0], n = nv.shape[1]
    cdef _Buf rows = _Buf(4 * K * n)
    right, left = np.empty(n), np.empty(n)
    cdef double[::1] r = right
    cdef double[::1] lf = left
    _rows(&xv[0], n, K, T, &nv[0, 0], stall, rows.p)
    _barriers(&xv[0], n, K, T, rows.p, &cl[0, 0], stall, eps, &r[0], &lf[0])
    return right, left


cdef void _reaching(const double* row, Py_ssize_t m, const double* level, Py_ssize_t n, bint rightward,
                    Py_ssize_t* stack, Py_ssize_t* out) noexcept nogil:
    """For each cell i the first j ≥ its start (i + 1 on a rightward row, n − 1 − i on a
    mirrored leftward one) with row[j] ≥ level[i], m where none: the linear scan's index,
    from one right-to-left pass that keeps the records of row[s:] (their values falling
    toward the stack's top, their indices too), bisected per cell. O(m + n log m); a row
    with a NaN (no order) is scanned."""
    cdef Py_ssize_t s, i, size = 0, lo, hi, mid
    cdef double lv
    for s in range(m):
        if isnan(row[s]):
            _scan(row, m, level, n, rightward, out)
            return
    for s in range(m - 1, -1, -1):
        while size > 0 and row[stack[size - 1]] <= row[s]:
            size -= 1
        stack[size] = s
        size += 1
        i = s - 1 if rightward else n - 1 - s
        if i < 0 or i >= n:
            continue
        lv = level[i]
        lo, hi = 0, size  # the first record below the level (records fall toward the top)
        while lo < hi:
            mid = (lo + hi) >> 1
            if not row[stack[mid]] >= lv:
                hi = mid
            else:
                lo = mid + 1
        out[i] = stack[lo - 1] if lo > 0 else m


cdef void _scan(const double* row, Py_ssize_t m, const double* level, Py_ssize_t n, bint rightward,
                Py_ssize_t* out) noexcept nogil:
    """:func:`_reaching` by the linear scan (barriers.first_reaching's answers)."""
    cdef Py_ssize_t i, j
    for i in range(n):
        out[i] = m
        for j in range(i + 1 if rightward else n - 1 - i, m):
            if row[j] >= level[i]:
                out[i] = j
                break


cdef void _rows(const double* x, Py_ssize_t n, Py_ssize_t K, double T, const double* nv, double stall,
                double* rows) noexcept nogil:
    """The 2K rows (2n each) barrier_sets searches: K rightward (f + s·θ over two periods,
    copy k then its next copy), K mirrored leftward (f − s·θ, reversed)."""
    cdef Py_ssize_t k, j, m = 2 * n, kk
    cdef double xs, val
    for k in range(K):
        kk = (k + 1) % K
        for j in range(m):
            if j < n:
                xs, val = x[j] + 0.0, nv[k * n + j]
            else:
                xs, val = x[j - n] + T, nv[kk * n + j - n]
            rows[k * m + j] = val + stall * xs
            rows[(K + k) * m + m - 1 - j] = val - stall * xs


# ------------------------------------------------------------ the classification

cdef struct BandC:
    double stall0, stall1, sigma, jaw, err, shallow


cdef BandC _band(band) except *:
    """A setvalued._Band's floats."""
    cdef BandC b
    b.stall0, b.stall1, b.sigma = band.stall[0], band.stall[1], band.sigma
    b.jaw, b.err, b.shallow = band.jaw_friction, band.err, band.shallow
    return b


cdef class _Pass:
    """One classification (setvalued._classify) in C buffers: n cells of K copies. ``x``
    holds 6n doubles: the nodes; the right and left barriers of each cell's greatest f
    (the final level); those of its least f (``near``); each cell's least sampled |f′|.
    ``perm`` holds 3n flags: right, left, rest possible. ``g``: the (n, 2, K) samples of
    f′ when asked for, else None."""
    cdef Py_ssize_t n, K
    cdef double* x
    cdef unsigned char* perm
    cdef object g
    cdef list rims
    cdef bint near, final

    def __dealloc__(self):
        free(self.x)
        free(self.perm)


cdef _Pass _pass(f, double T, const double* e, Py_ssize_t ne, const double* gr, Py_ssize_t ng, BandC b,
                 bint first, bint want_g):
    """setvalued._classify of the cells between the edges e[0:ne], the grid gr[0:ng] and
    f's breakpoints and extrema."""
    cdef const double[::1] kt = f.kink_thetas
    cdef Py_ssize_t N = 1 + ng + 2 * ne + kt.shape[0], n
    cdef _Buf xb = _Buf(N)
    cdef char* kink = <char*>malloc(N)
    if kink == NULL:
        raise MemoryError()
    try:
        n = _nodes(gr, ng, e, ne, &kt[0], kt.shape[0], T, xb.p, kink)
        return _sampled(f, T, n, xb.p, kink, b, first, want_g)
    finally:
        free(kink)


cdef _Pass _sampled(f, double T, Py_ssize_t n, const double* x, const char* kink, BandC b, bint first, bint want_g):
    """f′ and f just inside both ends of every cell in every copy (setvalued._samples;
    a kink's left limit apart), then :func:`_finish`."""
    cdef Py_ssize_t K = round(f.period / T), i, t, k, nt = n
    cdef double w
    cdef _Buf tb
    cdef Py_ssize_t* src = <Py_ssize_t*>malloc(n * sizeof(Py_ssize_t))
    if src == NULL:
        raise MemoryError()
    try:
        for i in range(n):
            if kink[i]:
                src[i] = nt
                nt += 1
            else:
                src[i] = i
        tb = _Buf(nt + 3 * nt * K)
        for i in range(n):
            w = (x[i + 1] if i < n - 1 else T) - x[i]
            tb.p[i] = x[i] + INSIDE * w
            if kink[i]:
                w = (x[i] if i > 0 else T) - x[i - 1 if i > 0 else n - 1]
                tb.p[src[i]] = x[i] - INSIDE * w
        for t in range(nt):
            for k in range(K):
                tb.p[nt + t * K + k] = tb.p[t] + (<double>k) * T if K > 1 else tb.p[t]
        _slopes(f, tb.p + nt, nt * K, tb.p + nt + nt * K, tb.p + nt + 2 * nt * K)
        return _finish(T, n, K, x, src, tb.p + nt + nt * K, tb.p + nt + 2 * nt * K, b, first, want_g)
    finally:
        free(src)


cdef _Pass _finish(double T, Py_ssize_t n, Py_ssize_t K, const double* x, const Py_ssize_t* src, const double* gf,
                   const double* vf, BandC b, bint first, bint want_g):
    """Permissions, basins and barriers of the sampled cells (setvalued._classify's rest)."""
    cdef _Pass p = _Pass.__new__(_Pass)
    cdef Py_ssize_t i, k
    p.n, p.K = n, K
    p.x = <double*>malloc(6 * n * sizeof(double))
    p.perm = <unsigned char*>calloc(3 * n, 1)
    if p.x == NULL or p.perm == NULL:
        raise MemoryError()
    cdef _Buf vb = _Buf(8 * n * K)
    cdef double* V = vb.p  # (n, 2, K) f at both ends of every cell
    cdef double* rows = V + 2 * n * K  # (2K, 2n)
    cdef double* nv = rows + 4 * n * K  # (K, n) f at the cells' starts
    cdef double* lv = nv + n * K  # (K, n) a level
    cdef double* bar = p.x + n
    _permissions(p, x, src, gf, vf, V, b, want_g)
    for k in range(K):
        for i in range(n):
            nv[k * n + i] = V[(i * 2) * K + k]
    p.rims = _basin_flags(p, nv, b.shallow)
    p.near = first and b.err > 0.0
    p.final = not (p.near and p.rims)
    _rows(x, n, K, T, nv, b.stall0, rows)
    if p.final:
        _levels(V, n, K, True, lv)
        _barriers(x, n, K, T, rows, lv, b.stall0, b.err, bar, bar + n)
    if p.near:
        _levels(V, n, K, False, lv)
        _barriers(x, n, K, T, rows, lv, b.stall0, b.err, bar + 2 * n, bar + 3 * n)
    return p


cdef void _permissions(_Pass p, const double* x, const Py_ssize_t* src, const double* gf, const double* vf,
                       double* V, BandC b, bint want_g) except *:
    """The nodes and the samples of every cell into p (and f at them into V, (n, 2, K)):
    setvalued._permissions, and each cell's least |f′|."""
    cdef Py_ssize_t n = p.n, K = p.K, i, s, k, row, kk
    cdef double gv, vv, a, size, least = 0.0, lo_move = b.stall0 - b.sigma
    cdef bint movable, either
    cdef double[:, :, ::1] G
    cdef unsigned char* P = p.perm
    if want_g:
        p.g = np.empty((n, 2, K))
        G = p.g
    for i in range(n):
        p.x[i] = x[i]
        for s in range(2):
            row = i if s == 0 else src[i + 1 if i < n - 1 else 0]
            for k in range(K):
                kk = (k + 1) % K if (s == 1 and i == n - 1 and K > 1) else k
                gv, vv = gf[row * K + kk], vf[row * K + kk]
                if want_g:
                    G[i, s, k] = gv
                V[(i * 2 + s) * K + k] = vv
                a, size = fabs(gv), fabs(vv)
                least = a if (s == 0 and k == 0) else _min(least, a)
                movable = a > _max(lo_move, SLOPE_NOISE * size)
                either = a <= b.sigma
                if movable and (gv < 0.0 or either):
                    P[i] = 1
                if movable and (gv > 0.0 or either):
                    P[n + i] = 1
                if a <= b.jaw * size + b.stall1 + b.sigma:
                    P[2 * n + i] = 1
        p.x[5 * n + i] = least


cdef list _basin_flags(_Pass p, const double* nv, double shallow):
    """The rims of the shallow basins of f at the cells' starts over the copies (nv, (K, n));
    their cells may move either way."""
    cdef Py_ssize_t n = p.n, i, k
    cdef char* mask = <char*>calloc(n * p.K, 1)
    if mask == NULL:
        raise MemoryError()
    try:
        rims = _basins(nv, n * p.K, shallow, mask)
        for k in range(p.K):
            for i in range(n):
                if mask[k * n + i]:
                    p.perm[i], p.perm[n + i] = 1, 1
        return rims
    finally:
        free(mask)


cdef void _levels(const double* V, Py_ssize_t n, Py_ssize_t K, bint top, double* lv) noexcept nogil:
    """(K, n): f's greater (``top``) or lesser value at each cell's two ends, per copy."""
    cdef Py_ssize_t i, k
    for k in range(K):
        for i in range(n):
            if top:
                lv[k * n + i] = _max(V[(i * 2) * K + k], V[(i * 2 + 1) * K + k])
            else:
                lv[k * n + i] = _min(V[(i * 2) * K + k], V[(i * 2 + 1) * K + k])


def classify(f, double T, edges, grid, band, bint first):
    """setvalued._classify's arrays: (x, right, left, rest, barrier_right, barrier_left,
    g (n, 2, K), rims, near), bit-identical to the numpy path."""
    if not _ready:
        _init()
    cdef const double[::1] e = np.ascontiguousarray(edges, dtype=float)
    cdef const double[::1] gr = np.ascontiguousarray(grid, dtype=float)
    cdef _Pass p = _pass(f, T, &e[0] if e.shape[0] else NULL, e.shape[0], &gr[0] if gr.shape[0] else NULL,
                         gr.shape[0], _band(band), first, True)
    return _arrays(p)


cdef tuple _arrays(_Pass p):
    """A pass as setvalued._classify's arrays."""
    cdef Py_ssize_t n = p.n, i
    x_out, found, flags = np.empty(n), np.empty((4, n)), np.empty((3, n), dtype=np.bool_)
    cdef double[::1] xo = x_out
    cdef double[:, ::1] fo = found
    cdef unsigned char[:, ::1] fl = flags.view(np.uint8)
    for i in range(n):
        xo[i] = p.x[i]
        fl[0, i], fl[1, i], fl[2, i] = p.perm[i], p.perm[n + i], p.perm[2 * n + i]
        fo[0, i], fo[1, i], fo[2, i], fo[3, i] = p.x[n + i], p.x[2 * n + i], p.x[3 * n + i], p.x[4 * n + i]
    return (x_out, flags[0], flags[1], flags[2], found[0] if p.final else _NONE, found[1] if p.final else _NONE, p.g,
            p.rims, (found[2], found[3]) if p.near else None)


# ---------------------------------------------------- setvalued._cells_of, fused

def set_bounds(f, double T, band, double tol_rad, contacts, tuple slopes, jaw):
    """setvalued._cells_of, setcells.bounds and rest_zones for a function whose crossings
    are all closed-form (no curve cells): the first pass, a second with the shallow
    basins' rims and the refined grid when it asks for them, then the bounds. (lower
    pieces, upper pieces, rest zones over T, over f's period), canonical TransferPieces
    and the same floats; None where the part may turn without end."""
    if not _ready:
        _init()
    _pieces_ready()
    cdef BandC b = _band(band)
    e1 = point_roots(contacts, slopes, jaw, ())
    cdef const double[::1] e = e1
    cdef _Pass p = _pass(f, T, &e[0] if e.shape[0] else NULL, e.shape[0], NULL, 0, b, True, False)
    grid = _refined(p, T, b)
    if p.rims or grid is not None:
        p = _again(f, T, b, contacts, e, p.rims, grid)
    cdef double P = f.period
    found = _final_bounds(p, T, tol_rad)
    if found is None:
        return None
    zones = _zones(p.x, p.n, T, p.perm + 2 * p.n, T, 1)
    return found[0], found[1], zones, zones if P == T else _zones(p.x, p.n, T, p.perm + 2 * p.n, P, p.K)


cdef _Pass _again(f, double T, BandC b, contacts, const double[::1] e, list rims, grid):
    """The second pass of setvalued._cells_of: the edges with where f crosses the rims,
    the grid where the first pass asked for it."""
    cdef Py_ssize_t ne = e.shape[0], nr = 0, ng = 0, i
    cdef const double[::1] r
    cdef const double[::1] g
    if rims:
        r = point_roots(contacts, (), None, tuple(rims))
        nr = r.shape[0]
    if grid is not None:
        g = grid
        ng = g.shape[0]
    cdef _Buf all_e = _Buf(ne + nr)
    for i in range(ne):
        all_e.p[i] = e[i]
    for i in range(nr):
        all_e.p[ne + i] = r[i]
    return _pass(f, T, all_e.p, ne + nr, &g[0] if ng else NULL, ng, b, False, False)


cdef object _refined(_Pass p, double T, BandC b):
    """setvalued._cells_of's grid of GRID_RAD inside the cells _to_refine marks, or None
    (none marked)."""
    if not p.near:
        return None
    cdef Py_ssize_t n = p.n, i, j, t = 0
    cdef _Buf ru = _Buf(4 * n)
    cdef _Buf mark = _Buf(n)
    _runs(p.x, n, T, p.perm, ru.p)
    if not _to_refine(p, ru.p, b.stall0 + b.sigma, mark.p):
        return None
    grid = np.linspace(0.0, T, max(8, <Py_ssize_t>ceil(T / GRID_RAD)), endpoint=False)
    cdef double[::1] g = grid
    for i in range(g.shape[0]):
        j = _bisect_right(p.x, n, g[i]) - 1
        if mark.p[j if j >= 0 else j + n] != 0.0:
            g[t] = g[i]
            t += 1
    return grid[:t]


cdef bint _to_refine(_Pass p, const double* ru, double slow_at, double* mark) noexcept:
    """setvalued._to_refine into mark (1.0 where marked, given the runs ru (4, n)):
    whether any cell is."""
    cdef Py_ssize_t n = p.n, i
    cdef const unsigned char* P = p.perm
    cdef bint all_r = True, all_l = True, bind = False, m
    for i in range(n):
        all_r = all_r and P[i] != 0
        all_l = all_l and P[n + i] != 0
    for i in range(n):
        m = ((P[i] != 0 and p.x[3 * n + i] < (INFINITY if all_r else ru[i]))
             or (P[n + i] != 0 and p.x[4 * n + i] > (-INFINITY if all_l else ru[2 * n + i])))
        mark[i] = 1.0 if m else 0.0
        bind = bind or m
    if not bind:
        return False
    for i in range(n):
        if p.x[5 * n + i] < slow_at and (P[i] != 0 or P[n + i] != 0):
            mark[i] = 1.0
    return True


cdef object _final_bounds(_Pass p, double T, double tol):
    """setcells.bounds of the final pass: (lower, upper) canonical pieces, or None."""
    cdef Py_ssize_t n = p.n, i
    cdef _Buf b = _Buf(6 * n)
    cdef double* ru = b.p
    cdef bint all_r = True, all_l = True
    _runs(p.x, n, T, p.perm, ru)
    for i in range(n):
        all_r = all_r and p.perm[i] != 0
        all_l = all_l and p.perm[n + i] != 0
    for i in range(n):
        b.p[4 * n + i] = INFINITY if all_r else ru[i]
        b.p[5 * n + i] = -INFINITY if all_l else ru[2 * n + i]
    return _bounds(p.x, n, T, p.perm, b.p + 4 * n, b.p + 5 * n, ru, p.x + n, p.x + 2 * n, tol, True)


cdef tuple _zones(const double* nodes, Py_ssize_t n, double T, const unsigned char* rest, double P, Py_ssize_t K):
    """setcells.rest_zones over K copies of the cells (the _lookups kernel's loops)."""
    cdef Py_ssize_t N = n * (K if K > 1 else 1), i, k, na = 0, nb = 0, nr = 0
    cdef _Buf buf = _Buf(4 * N)
    cdef double* x = buf.p
    cdef double* a = buf.p + N
    cdef double* b = buf.p + 2 * N
    cdef unsigned char* r = <unsigned char*>(buf.p + 3 * N)
    cdef list out = []
    for k in range(N // n):  # (nodes + k·T for every copy; one copy as it is)
        for i in range(n):
            x[k * n + i] = nodes[i] + (<double>k) * T if K > 1 else nodes[i]
            r[k * n + i] = rest[i] != 0
            nr += r[k * n + i]
    if nr == N:
        return ((0.0, P),)
    if nr == 0:
        return ()
    for i in range(N):
        if r[i] and not r[i - 1 if i > 0 else N - 1]:
            a[na] = x[i]
            na += 1
        if r[i] and not r[i + 1 if i + 1 < N else 0]:
            b[nb] = x[i + 1] if i + 1 < N else P
            nb += 1
    if r[0] and r[N - 1]:  # the zone through 0: from the last start to the first end
        a[na - 1] -= P
        for i in range(na):
            out.append((a[i], b[i + 1 if i + 1 < nb else 0]))
    else:
        for i in range(min(na, nb)):
            out.append((a[i], b[i]))
    return tuple(out)


# ---------------------------------------------------------------- setcells passes

cdef inline bint _flag(const unsigned char* perm, Py_ssize_t n, int q, Py_ssize_t i) noexcept nogil:
    """Row q of setcells' run flags [R, ~L & ~S, L, ~R & ~S] at cell i (perm: R, L, S)."""
    if q == 0:
        return perm[i] != 0
    if q == 1:
        return perm[n + i] == 0 and perm[2 * n + i] == 0
    if q == 2:
        return perm[n + i] != 0
    return perm[i] == 0 and perm[2 * n + i] == 0


cdef inline double _at(const double* x, Py_ssize_t n, double T, Py_ssize_t j) noexcept nogil:
    """Cells.at: the lifted start of cell j (any integer; a few periods away at most)."""
    cdef Py_ssize_t i = j, lift = 0
    while i < 0:
        i += n
        lift -= 1
    while i >= n:
        i -= n
        lift += 1
    return x[i] + (<double>lift) * T


cdef void _runs(const double* x, Py_ssize_t n, double T, const unsigned char* perm, double* o) noexcept nogil:
    """setcells.Cells.runs into o (4, n): where the right-movable and forced-right runs
    containing each cell end and the left ones start (setcells._run_bounds over three
    copies, then Cells.at)."""
    cdef Py_ssize_t t, j
    cdef int q
    for q in range(2):  # the first False at or after each cell, 4n where none
        j = 4 * n
        for t in range(3 * n - 1, n - 1, -1):
            if not _flag(perm, n, q, t - n if t < 2 * n else t - 2 * n):
                j = t - n
            if t < 2 * n:
                o[q * n + t - n] = _at(x, n, T, j)
    for q in range(2, 4):  # the last False at or before each cell, plus one; −4n + 1 where none
        j = -4 * n
        for t in range(2 * n):
            if not _flag(perm, n, q, t if t < n else t - n):
                j = t - n
            if t >= n:
                o[q * n + t - n] = _at(x, n, T, j + 1)


cdef class _Cells:
    """setcells.Cells' nodes and flags copied into C buffers (x: n doubles, perm: R, L, S)."""
    cdef Py_ssize_t n
    cdef _Buf x
    cdef unsigned char* perm

    def __cinit__(self, x, R, L, S):
        cdef const double[:] xv = x
        cdef const unsigned char[:] r = R.view(np.uint8)
        cdef const unsigned char[:] lf = L.view(np.uint8)
        cdef const unsigned char[:] st = S.view(np.uint8)
        cdef Py_ssize_t n = xv.shape[0], i
        self.n, self.x = n, _Buf(n)
        self.perm = <unsigned char*>malloc(max(3 * n, 1))
        if self.perm == NULL:
            raise MemoryError()
        for i in range(n):
            self.x.p[i] = xv[i]
            self.perm[i], self.perm[n + i], self.perm[2 * n + i] = r[i], lf[i], st[i]

    def __dealloc__(self):
        free(self.perm)


def runs(x, double T, R, L, S):
    """setcells.Cells.runs: (4, n) lifted cell starts (:func:`_runs`)."""
    cdef _Cells c = _Cells(x, R, L, S)
    out = np.empty((4, c.n))
    cdef double[:, ::1] o = out
    if c.n:
        _runs(c.x.p, c.n, T, c.perm, &o[0, 0])
    return out


def bound_pieces(x, double T, R, L, S, run_right, run_left, cell_runs, barrier_right, barrier_left, double tol):
    """setcells.bounds up to the pieces: the (start, end, value or None) triples of the
    lower and upper functions after setcells._monotone and _tf's merge; None where the
    part may turn without end."""
    cdef _Cells c = _Cells(x, R, L, S)
    cdef Py_ssize_t n = c.n, i
    cdef const double[:] rr = run_right
    cdef const double[:] rl = run_left
    cdef const double[:, :] ru = cell_runs
    cdef const double[:] b_r = barrier_right
    cdef const double[:] b_l = barrier_left
    cdef _Buf b = _Buf(8 * n)
    for i in range(n):
        b.p[i], b.p[n + i], b.p[2 * n + i], b.p[3 * n + i] = ru[0, i], ru[1, i], ru[2, i], ru[3, i]
        b.p[4 * n + i], b.p[5 * n + i], b.p[6 * n + i], b.p[7 * n + i] = rr[i], rl[i], b_r[i], b_l[i]
    return _bounds(c.x.p, n, T, c.perm, b.p + 4 * n, b.p + 5 * n, b.p, b.p + 6 * n, b.p + 7 * n, tol, False)


cdef object _bounds(const double* x, Py_ssize_t n, double T, const unsigned char* perm, const double* rr,
                    const double* rl, const double* ru, const double* b_r, const double* b_l, double tol, bint pieces):
    """setcells.bounds up to the merged pieces of (lower, upper): triples, or canonical
    TransferPieces (``pieces``); None where the part may turn without end. ru: the runs
    (4, n)."""
    cdef _Buf b = _Buf(3 * n)
    cdef double* up = b.p
    cdef double* lo = b.p + n
    cdef double* ends = b.p + 2 * n
    cdef Py_ssize_t i
    for i in range(n):
        up[i] = _min(rr[i], b_r[i]) if perm[i] else (NAN if perm[2 * n + i] else ru[3 * n + i])
        lo[i] = _max(rl[i], b_l[i]) if perm[n + i] else (NAN if perm[2 * n + i] else ru[n + i])
        if (perm[i] and not isfinite(up[i])) or (perm[n + i] and not isfinite(lo[i])):
            return None
        ends[i] = x[i + 1] if i < n - 1 else x[0] + T
    _monotone(x, ends, up, lo, n, T)
    if not pieces:
        return _merge(x, ends, lo, n, tol), _merge(x, ends, up, n, tol)
    return _merged(x, ends, lo, n, T, tol), _merged(x, ends, up, n, T, tol)


cdef void _monotone(const double* x, const double* ends, double* up, double* lo, Py_ssize_t n, double T) noexcept nogil:
    """setcells._monotone in place: upper raised, lower lowered where barriers made them dip."""
    cdef Py_ssize_t i
    cdef double top, bottom, acc, ext, seq, nxt
    ext = ends[0] if isnan(up[0]) else up[0]  # the greatest top
    for i in range(1, n):
        ext = _max(ext, ends[i] if isnan(up[i]) else up[i])
    acc = ext - T  # running maximum of the tops before each cell
    for i in range(n):
        top = ends[i] if isnan(up[i]) else up[i]
        bottom = x[i] if isnan(up[i]) else up[i]
        if i > 0:
            acc = _max(acc, seq)
        seq = top + 0.0
        if bottom < acc:
            up[i] = _max(acc, top + 0.0)
    ext = x[0] if isnan(lo[0]) else lo[0]  # the least bottom
    for i in range(1, n):
        ext = _min(ext, x[i] if isnan(lo[i]) else lo[i])
    acc = ext + T  # running minimum of the bottoms after each cell
    for i in range(n - 1, -1, -1):
        top = ends[i] if isnan(lo[i]) else lo[i]
        bottom = x[i] if isnan(lo[i]) else lo[i]
        if i < n - 1:
            acc = _min(acc, nxt)
        nxt = bottom + 0.0
        if top > acc:
            lo[i] = _min(acc, bottom + 0.0)


cdef list _merge(const double* x, const double* ends, const double* v, Py_ssize_t n, double tol):
    """setcells._tf's merge: neighbours with the same value to tol (or both ramps) as one
    piece (start, end, value or None)."""
    cdef list out = []
    cdef Py_ssize_t i, first = 0
    for i in range(1, n + 1):
        if i < n and ((isnan(v[i]) and isnan(v[i - 1])) or fabs(v[i] - v[i - 1]) <= tol):
            continue
        out.append((x[first], ends[i - 1], None if isnan(v[first]) else v[first]))
        first = i
    return out


cdef tuple _merged(const double* x, const double* ends, const double* v, Py_ssize_t n, double T, double tol):
    """:func:`_merge` then transfer.canonical (setcells._pieces_tf): TransferPieces."""
    cdef Pieces q
    cdef Py_ssize_t i, first = 0
    _pieces_new(&q, n)
    try:
        for i in range(1, n + 1):
            if i < n and ((isnan(v[i]) and isnan(v[i - 1])) or fabs(v[i] - v[i - 1]) <= tol):
                continue
            _put(&q, x[first], ends[i - 1], v[first], isnan(v[first]))
            first = i
        _canon(&q, T, tol)
        return _objects(&q)
    finally:
        _pieces_free(&q)


# ------------------------------------------------------------ transfer.canonical

cdef inline object _item(object p, Py_ssize_t i):
    """Field i of a piece (a tuple subclass): no bounds check, no index object."""
    return <object>PyTuple_GET_ITEM(p, i)


cdef object _Piece = None
cdef object _new_piece = None


cdef inline object _piece(object a, object b, object v):
    """TransferPiece(a, b, v), as its own __new__ makes it (tuple.__new__), one call less."""
    return _new_piece(_Piece, (a, b, v))


cdef inline object _shift(object p, double d):
    """TransferPiece.shifted."""
    v = _item(p, 2)
    return _piece(<double>_item(p, 0) + d, <double>_item(p, 1) + d, None if v is None else <double>v + d)  # as p.shifted


cdef void _pieces_ready() except *:
    """The piece type (transfer imports this module: read it at first use) and the constants."""
    global _Piece, _new_piece
    if _Piece is None:
        from algrasp.planning.transfer import TransferPiece
        _Piece, _new_piece = TransferPiece, tuple.__new__
    if not _ready:
        _init()


def canonical(list pieces, double period, double tol_rad):
    """transfer.canonical in typed loops: the same pieces, the same floats."""
    _pieces_ready()
    for p in pieces:
        if type(p) is not _Piece:  # _item reads tuples' slots unchecked
            raise TypeError(f"canonical: a piece must be a TransferPiece, not {type(p).__name__}")
    return _canonical(pieces, period, tol_rad)


cdef list _canonical(list pieces, double period, double tol_rad):
    """transfer.canonical of TransferPieces (checked by the caller)."""
    cdef list merged = []
    cdef object last_value = 0.0, value
    cdef object p, last
    cdef double start, top, key, k
    cdef Py_ssize_t i, j, n
    for p in pieces:
        value = _item(p, 2)
        n = len(merged)
        if n and ((value is None) if last_value is None else
                  (value is not None and fabs(<double>last_value - <double>value) <= tol_rad)):
            merged[n - 1] = _piece(_item(merged[n - 1], 0), _item(p, 1), last_value)  # (no wraparound here)
        else:
            merged.append(p)
            last_value = value
    n = len(merged)
    if n > 1:
        last, p = merged[n - 1], merged[0]
        if (_item(p, 2) is None) if _item(last, 2) is None else (
                _item(p, 2) is not None and fabs(<double>_item(last, 2) - (<double>_item(p, 2) + period)) <= tol_rad):
            merged.pop()
            merged[0] = _piece(<double>_item(last, 0) - period, _item(p, 1),
                               None if _item(last, 2) is None else <double>_item(last, 2) - period)
    top = period - tol_rad
    cdef list out = []
    for p in merged:
        start = _item(p, 0)
        k = floor(start / period + ROUNDING) if start >= 0 else floor(start / period)
        if k != 0.0:
            p = _shift(p, (-k) * period)
        out.append(_shift(p, -period) if <double>_item(p, 0) >= top else p)
    n = len(out)
    for i in range(1, n):  # stable insertion sort by start (few pieces)
        p = out[i]
        key = _item(p, 0)
        j = i - 1
        while j >= 0 and key < <double>_item(out[j], 0):
            out[j + 1] = out[j]
            j -= 1
        out[j + 1] = p
    return out


# ------------------------------------------------- transfer.canonical, on arrays

cdef struct Pieces:
    Py_ssize_t n, cap
    double* s  # starts
    double* e  # ends
    double* v  # step values (not read on ramps)
    char* ramp


cdef int _pieces_new(Pieces* q, Py_ssize_t cap) except -1:
    """Room for ``cap`` pieces (free with _pieces_free)."""
    cap = max(cap, 1)
    q.n, q.cap = 0, cap
    q.s = <double*>malloc(3 * cap * sizeof(double))
    q.ramp = <char*>malloc(cap)
    if q.s == NULL or q.ramp == NULL:
        free(q.s)
        free(q.ramp)
        q.s, q.ramp = NULL, NULL
        raise MemoryError()
    q.e, q.v = q.s + cap, q.s + 2 * cap
    return 0


cdef inline void _pieces_free(Pieces* q) noexcept nogil:
    free(q.s)
    free(q.ramp)
    q.s, q.ramp = NULL, NULL


cdef inline void _put(Pieces* q, double s, double e, double v, bint ramp) noexcept nogil:
    """Append a piece (the caller made the room)."""
    q.s[q.n], q.e[q.n], q.v[q.n], q.ramp[q.n] = s, e, v, ramp
    q.n += 1


cdef void _canon(Pieces* q, double period, double tol) noexcept nogil:
    """:func:`_canonical` in place: neighbours merged (also across the wrap), the first
    start put in [0, period), sorted; the same floats."""
    cdef Py_ssize_t i, j, m = 0
    cdef double lv = 0.0, k, d
    cdef bint lramp = False
    for i in range(q.n):
        if m and (q.ramp[i] != 0 if lramp else (q.ramp[i] == 0 and fabs(lv - q.v[i]) <= tol)):
            q.e[m - 1] = q.e[i]  # the merged piece keeps its start and value
        else:
            q.s[m], q.e[m], q.v[m], q.ramp[m] = q.s[i], q.e[i], q.v[i], q.ramp[i]
            lv, lramp = q.v[i], q.ramp[i] != 0
            m += 1
    if m > 1 and (q.ramp[0] != 0 if q.ramp[m - 1] else (q.ramp[0] == 0 and
                                                          fabs(q.v[m - 1] - (q.v[0] + period)) <= tol)):
        q.s[0] = q.s[m - 1] - period
        if not q.ramp[0]:
            q.v[0] = q.v[m - 1] - period
        m -= 1
    q.n = m
    for i in range(m):
        k = floor(q.s[i] / period + ROUNDING) if q.s[i] >= 0 else floor(q.s[i] / period)
        if k != 0.0:
            _shift_at(q, i, (-k) * period)
        if q.s[i] >= period - tol:
            _shift_at(q, i, -period)
    _sort_pieces(q)


cdef inline void _shift_at(Pieces* q, Py_ssize_t i, double d) noexcept nogil:
    """TransferPiece.shifted in place."""
    q.s[i], q.e[i] = q.s[i] + d, q.e[i] + d
    if not q.ramp[i]:
        q.v[i] = q.v[i] + d


cdef void _sort_pieces(Pieces* q) noexcept nogil:
    """Stable insertion sort by start (few pieces)."""
    cdef Py_ssize_t i, j
    cdef double s, e, v
    cdef char r
    for i in range(1, q.n):
        s, e, v, r = q.s[i], q.e[i], q.v[i], q.ramp[i]
        j = i - 1
        while j >= 0 and s < q.s[j]:
            q.s[j + 1], q.e[j + 1], q.v[j + 1], q.ramp[j + 1] = q.s[j], q.e[j], q.v[j], q.ramp[j]
            j -= 1
        q.s[j + 1], q.e[j + 1], q.v[j + 1], q.ramp[j + 1] = s, e, v, r


cdef tuple _objects(const Pieces* q):
    """The pieces as TransferPieces."""
    cdef Py_ssize_t i
    return tuple([_piece(q.s[i], q.e[i], None if q.ramp[i] else q.v[i]) for i in range(q.n)])


# ------------------------------------------------------ TransferFunction.compose_after

cdef struct Table:
    double first, P
    Py_ssize_t n
    double* starts  # n piece starts
    double* after  # n + 1: [the last piece's value, *the values], NaN on ramps


cdef int _table_of(F, Table* t) except -1:
    """F._floats in C, read from F's pieces (the same floats); free with _table_free."""
    cdef tuple pieces = F.pieces
    cdef Py_ssize_t n = len(pieces), i
    if n == 0:
        raise IndexError("tuple index out of range")
    for p in pieces:
        if type(p) is not _Piece:  # _item reads tuples' slots unchecked
            raise TypeError("compose: pieces must be TransferPieces")
    t.starts = <double*>malloc((2 * n + 1) * sizeof(double))
    if t.starts == NULL:
        raise MemoryError()
    t.after, t.n, t.P = t.starts + n, n, F.period
    for i in range(n):
        p = <object>PyTuple_GET_ITEM(pieces, i)
        t.starts[i] = <double>_item(p, 0)
        v = _item(p, 2)
        t.after[i + 1] = NAN if v is None else <double>v
    t.after[0], t.first = t.after[n], t.starts[0]
    return 0


cdef Py_ssize_t _lifted_starts(const Table* t, double a, double b, double** out) except -1:
    """TransferFunction._lifted_starts: every piece start lifted over [a, b] (with a
    period to spare), sorted, into a malloc'd array (the caller frees it)."""
    cdef double P = t.P
    cdef Py_ssize_t k0 = <Py_ssize_t>floor((a - t.first) / P) - 1, k1 = <Py_ssize_t>ceil((b - t.first) / P) + 1
    cdef Py_ssize_t ns = t.n, n = (k1 - k0 + 1) * ns, i, k, j = 0
    cdef double* c = <double*>malloc(max(n, 1) * sizeof(double))
    if c == NULL:
        raise MemoryError()
    for k in range(k0, k1 + 1):
        for i in range(ns):
            c[j] = t.starts[i] + (<double>k) * P
            j += 1
    _insertion_sort(c, n)  # the copies are sorted runs
    out[0] = c
    return n


def compose(outer, inner, double tol_rad):
    """TransferFunction.compose_after's pieces (outer ∘ inner, canonical), the same
    floats: inner's steps read outer at their values, its ramps cut at outer's lifted
    starts and read at each cell's middle."""
    _pieces_ready()
    cdef Table t
    _table_of(outer, &t)
    try:
        return _compose(&t, inner, tol_rad)
    finally:
        free(t.starts)


cdef tuple _compose(const Table* t, inner, double tol_rad):
    """:func:`compose` of the outer function's table: canonical TransferPieces."""
    cdef tuple pieces = inner.pieces
    cdef Py_ssize_t m = len(pieces), nc = 0, i
    cdef double* cuts = NULL
    cdef Pieces cells
    cells.s, cells.ramp = NULL, NULL
    if any(type(p) is not _Piece for p in pieces):
        raise TypeError("compose: pieces must be TransferPieces")  # _item reads tuples' slots unchecked
    try:
        for i in range(m):
            if _item(<object>PyTuple_GET_ITEM(pieces, i), 2) is None:  # a ramp: the lifted starts cut it
                nc = _lifted_starts(t, _least_start(pieces), _greatest_end(pieces), &cuts)
                break
        _pieces_new(&cells, m * (nc + 1))
        _cells(pieces, cuts, nc, &cells)
        for i in range(cells.n):  # outer read at each step's value, each ramp cell's middle (in v)
            _read(t, &cells, i)
        _canon(&cells, inner.period, tol_rad)
        return _objects(&cells)
    finally:
        free(cuts)
        _pieces_free(&cells)


cdef void _cells(tuple pieces, const double* cuts, Py_ssize_t nc, Pieces* cells) except *:
    """inner's steps as they are; its ramps cut at the lifted starts (ramp flag set, the
    cell's middle in v: no rounding at boundaries)."""
    cdef Py_ssize_t i, j, q
    cdef double ps, pe, c, prev
    for p in pieces:
        v = _item(p, 2)
        ps, pe = _item(p, 0), _item(p, 1)
        if v is not None:
            _put(cells, ps, pe, <double>v, False)
            continue
        i, j = _bisect_right(cuts, nc, ps), _bisect_right(cuts, nc, pe)
        prev = ps
        for q in range(i, j + 1):
            if q < j:
                c = cuts[q]
                if not (ps < c < pe):
                    continue
            else:
                c = pe
            _put(cells, prev, c, 0.5 * (prev + c), True)
            prev = c


cdef inline void _read(const Table* t, Pieces* cells, Py_ssize_t i) noexcept nogil:
    """Cell i of the composition: outer's step value at its probe, else inner's own (its
    step's value, or a ramp)."""
    cdef double v = _value_at(t, cells.v[i])
    if v == v:
        cells.v[i], cells.ramp[i] = v, False


cdef double _least_start(tuple pieces) except? -1:
    """min(p.start for p in pieces) (Python's: the first of equals)."""
    cdef double lo = _item(pieces[0], 0)
    for p in pieces:
        lo = _min_py(lo, _item(p, 0))
    return lo


cdef double _greatest_end(tuple pieces) except? -1:
    """max(p.end for p in pieces) (Python's: the first of equals)."""
    cdef double hi = _item(pieces[0], 1)
    for p in pieces:
        hi = _max_py(hi, _item(p, 1))
    return hi


cdef inline double _min_py(double a, double b) noexcept nogil:
    """Python's min(a, b) of floats (the first of equals)."""
    return b if b < a else a


cdef inline double _max_py(double a, double b) noexcept nogil:
    """Python's max(a, b) of floats (the first of equals)."""
    return b if b > a else a


cdef inline double _value_at(const Table* t, double x) noexcept nogil:
    """TransferFunction.values_at of one θ: the lifted value of the step holding it, NaN
    on a ramp (its float path; the vectorised one makes the same floats)."""
    cdef double off = (floor((x - t.first) / t.P) + 0.0) * t.P
    cdef Py_ssize_t at = _bisect_right(t.starts, t.n, x - off)
    return t.after[at if at > 1 else 1] + off


cdef inline double _applied(const Table* t, double x) noexcept nogil:
    """TransferFunction.apply_floats of one θ (steps_floats's lookup, θ itself on ramps)."""
    cdef double kP = floor((x - t.first) / t.P) * t.P
    cdef double v = kP + t.after[_bisect_right(t.starts, t.n, x - kP)]
    return x if v != v else v


def compose_sets(outer_lower, outer_upper, inner_lower, inner_upper, tuple inner_outcomes, tuple outer_outcomes,
                 double symmetry, double T, Py_ssize_t copies, double tol_rad):
    """SetTransfer.compose_after: the composed lower and upper pieces (canonical), and the
    outer function's outcomes in each of ``copies`` copies of its symmetry that meet the
    image of one of the inner's outcomes (SetTransfer._meeting), the same floats."""
    _pieces_ready()
    cdef Table lo, up
    lo.starts = up.starts = NULL
    try:
        _table_of(outer_lower, &lo)
        _table_of(outer_upper, &up)
        return (_compose(&lo, inner_lower, tol_rad), _compose(&up, inner_upper, tol_rad),
                _meeting(&lo, &up, inner_outcomes, outer_outcomes, symmetry, T, copies))
    finally:
        free(lo.starts)
        free(up.starts)


cdef tuple _meeting(const Table* lo, const Table* up, tuple inner, tuple outer, double symmetry, double T,
                    Py_ssize_t copies):
    """SetTransfer._meeting of the arcs [lower(a), upper(b)] of the inner outcomes [a, b]."""
    cdef Py_ssize_t m = len(inner), k, i
    cdef double a, b, c, start
    cdef _Buf arcs = _Buf(2 * m)  # each arc's start and width
    for i in range(m):
        arc = inner[i]
        arcs.p[i] = _applied(lo, <double>arc[0])
        arcs.p[m + i] = _applied(up, <double>arc[1]) - arcs.p[i]
    cdef list kept = []
    for k in range(copies):
        c = (<double>k) * symmetry
        for out in outer:
            a, b = <double>out[0] + c, <double>out[1] + c
            for i in range(m):
                start = _mod(a - arcs.p[i], T)  # the outcome's start relative to the arc's
                if start <= arcs.p[m + i] or start + (b - a) >= T:
                    kept.append((a, b))
                    break
    return tuple(kept)


# ------------------------------------------------------------ placement._push_hull

def push_hull(push_lower, push_upper, double P, double tol_rad):
    """placement._push_hull's pieces (canonical): the pointwise min of the identity of
    period P, the push's lower bound and that bound shifted by π; the max likewise of the
    upper bound (placement.pointwise's cells and extremes), the same floats."""
    _pieces_ready()
    return _hull(push_lower, P, False, tol_rad), _hull(push_upper, P, True, tol_rad)


cdef tuple _hull(F, double P, bint take_max, double tol):
    """placement.pointwise([identity(P), F, shifted(F, π)], take_max, tol)'s pieces."""
    cdef double T = F.period
    cdef tuple own = F.pieces
    cdef Py_ssize_t no = len(own), i
    cdef Pieces moved, out
    cdef Table tf, ts
    moved.s = out.s = tf.starts = ts.starts = NULL
    moved.ramp = out.ramp = NULL
    try:
        _table_of(F, &tf)  # (checks the pieces)
        _pieces_new(&moved, no)
        for i in range(no):  # placement.shifted(F, π): each piece shifted by −π, canonical
            p = <object>PyTuple_GET_ITEM(own, i)
            v = _item(p, 2)
            _put(&moved, <double>_item(p, 0) + (-PI), <double>_item(p, 1) + (-PI),
                 0.0 if v is None else <double>v + (-PI), v is None)
        _canon(&moved, T, 0.0)
        _table_arrays(&moved, T, &ts)
        _pieces_new(&out, 2 * (2 + no + moved.n))
        _extremes(&tf, _item(own[0], 2) is None and no == 1, &ts, moved.ramp[0] != 0 and moved.n == 1, P, take_max,
                  &out)
        _canon(&out, P, tol)
        return _objects(&out)
    finally:
        free(tf.starts)
        free(ts.starts)
        _pieces_free(&moved)
        _pieces_free(&out)


cdef int _extremes(const Table* tf, bint f_identity, const Table* ts, bint s_identity, double P, bint take_max,
                   Pieces* out) except -1:
    """The cells between every piece start of the identity (from its start, 0) and the
    two functions, and on each the extreme of the identity and the steps holding its
    middle (placement.pointwise's loop, placement._extreme), into ``out``."""
    cdef Py_ssize_t ncell = 0, i, k, nconst, nf = 0, room = 2 + tf.n + ts.n
    cdef _Buf buf = _Buf(3 * room)
    cdef double* cuts = buf.p
    cdef double* mids = buf.p + room
    cdef double* ends = buf.p + 2 * room
    cdef const Table* live[2]
    cdef double c = 0.0, v
    cdef Py_ssize_t nc = _cut_list(tf, ts, P, cuts)
    for i in range(nc - 1):
        if cuts[i + 1] - cuts[i] > 0.0:
            mids[ncell], ends[ncell] = 0.5 * (cuts[i] + cuts[i + 1]), cuts[i + 1]
            cuts[ncell] = cuts[i]  # (ncell ≤ i: read before written)
            ncell += 1
    if not f_identity:  # the identity is a ramp everywhere: no lookup
        live[nf] = tf
        nf += 1
    if not s_identity:
        live[nf] = ts
        nf += 1
    for i in range(ncell):
        nconst = 0
        for k in range(nf):
            v = _step_at(live[k], mids[i])
            if v == v:
                if nconst == 0 or (v > c if take_max else v < c):  # max/min: the first of equals
                    c = v
                nconst += 1
        _extreme(out, cuts[i], ends[i], nconst, c, take_max)
    return 0


cdef void _extreme(Pieces* out, double lo, double hi, Py_ssize_t nconst, double c, bint take_max) noexcept nogil:
    """placement._extreme with the identity always among the functions (a ramp)."""
    if nconst == 0:
        _put(out, lo, hi, 0.0, True)
    elif c >= hi if take_max else c <= lo:
        _put(out, lo, hi, c, False)
    elif (c <= lo) if take_max else (c >= hi):
        _put(out, lo, hi, 0.0, True)
    elif take_max:
        _put(out, lo, c, c, False)
        _put(out, c, hi, 0.0, True)
    else:
        _put(out, lo, c, 0.0, True)
        _put(out, c, hi, c, False)


cdef inline double _step_at(const Table* t, double x) noexcept nogil:
    """TransferFunction.steps_floats of one θ: the lifted value of the step holding it,
    NaN on a ramp."""
    cdef double kP = floor((x - t.first) / t.P) * t.P
    return kP + t.after[_bisect_right(t.starts, t.n, x - kP)]


cdef Py_ssize_t _cut_list(const Table* tf, const Table* ts, double P, double* out) noexcept nogil:
    """placement._cuts of [identity(P), F, shifted F] from 0 (the identity's start): the
    distinct piece starts lifted into [0, P], with 0 and P, sorted (the first of equal
    values kept, as the set does)."""
    cdef Py_ssize_t n = 2, i, j, f
    cdef double x
    cdef const Table* t
    out[0], out[1] = 0.0, 0.0 + P
    for f in range(2):
        t = tf if f == 0 else ts
        for i in range(t.n):
            n = _add_distinct(out, n, 0.0 + _mod(t.starts[i] - 0.0, P))
    j = 0
    for i in range(n):  # kept in [0, P], then sorted (distinct values)
        if 0.0 <= out[i] <= 0.0 + P:
            out[j] = out[i]
            j += 1
    _insertion_sort(out, j)
    return j


cdef int _table_arrays(const Pieces* q, double P, Table* t) except -1:
    """:func:`_table_of` of pieces of period P in arrays."""
    cdef Py_ssize_t n = q.n, i
    t.starts = <double*>malloc((2 * n + 1) * sizeof(double))
    if t.starts == NULL:
        raise MemoryError()
    t.after, t.n, t.P = t.starts + n, n, P
    for i in range(n):
        t.starts[i] = q.s[i]
        t.after[i + 1] = NAN if q.ramp[i] else q.v[i]
    t.after[0], t.first = t.after[n], t.starts[0]
    return 0


# ---------------------------------------------------------------- edges._contacts

def contacts(tuple cells, centers, radii, com):
    """edges._grid's point-like contacts on a hull without curve features: (ρ, R, φ0, ψ_a,
    ψ_b) of the contact cells (near, far, ψ_a, ψ_b; near −1: the centre of mass) with ρ > 0,
    the same floats (hypot and arctan2 through numpy, on the same (m, 2) array's views)."""
    cdef const double[:, :] cen = centers
    cdef const double[:] rad = radii
    cdef Py_ssize_t m = len(cells), i, near, far, live = 0
    cdef double cx = com[0], cy = com[1], nx, ny, fx, fy
    delta_xy, rest = np.empty((m, 2)), np.empty((3, m))
    cdef double[:, ::1] d = delta_xy
    cdef double[:, ::1] r = rest  # R, ψ_a, ψ_b
    for i in range(m):
        cell = <object>PyTuple_GET_ITEM(cells, i)
        if type(cell) is not tuple or len(cell) != 4:  # _item reads tuples' slots unchecked
            raise TypeError("contacts: a cell must be a tuple (near, far, a, b)")
        near, far = <Py_ssize_t>_item(cell, 0), <Py_ssize_t>_item(cell, 1)
        nx, ny, fx, fy = cx, cy, cx, cy  # row −1: the centre of mass (the radius's near contact)
        if near >= 0:
            nx, ny = cen[near, 0], cen[near, 1]
        if far >= 0:
            fx, fy = cen[far, 0], cen[far, 1]
        d[i, 0], d[i, 1] = nx - fx, ny - fy
        r[0, i] = (0.0 if near < 0 else rad[near]) + (0.0 if far < 0 else rad[far])
        r[1, i], r[2, i] = <double>_item(cell, 2), <double>_item(cell, 3)
    rho = np.hypot(delta_xy[:, 0], delta_xy[:, 1])
    cdef const double[:] rh = rho
    for i in range(m):
        live += rh[i] > 0.0
    if live == m:  # no concentric contacts (a polygon's cells): nothing to leave out
        return rho, rest[0], np.arctan2(delta_xy[:, 1], delta_xy[:, 0]), rest[1], rest[2]
    keep = rho > 0.0
    return (rho[keep], rest[0][keep], np.arctan2(delta_xy[keep, 1], delta_xy[keep, 0]), rest[1][keep],
            rest[2][keep])


# ------------------------------------------------------- symmetry._none_by_runs

def none_by_runs(f, double theta, double value, double threshold, const double[::1] shifts, double slack):
    """symmetry._none_by_runs past its checks (no curve feature, the shifts P/k of f's
    period, ascending): whether every shifted point θ + P/k lies more than the threshold
    and ``slack`` · f's largest extremum above f(θ) = ``value``, judged at the first and
    last shift inside each run of f; f itself evaluated through f.values."""
    cdef tuple runs = f.runs
    cdef double P = f.period, top = -INFINITY, guard
    cdef Py_ssize_t nr = len(runs), n = 0, i, j, a, b, np_ = 0
    cdef _Buf buf = _Buf(nr + 2 + 2 * (nr + 1))
    cdef double* cuts = buf.p
    cdef double* picks = buf.p + nr + 2
    for run in runs:
        cuts[n] = _mod(<double>_item(run, 0) - theta, P)  # run ends as offsets from θ
        n += 1
    cuts[n], cuts[n + 1] = 0.0, P
    n = _distinct(cuts, n + 2)
    for i in range(n - 1):
        a, b = _bisect_left(&shifts[0], shifts.shape[0], cuts[i]), _bisect_left(&shifts[0], shifts.shape[0], cuts[i + 1])
        if b > a:
            picks[np_], picks[np_ + 1] = theta + shifts[a], theta + shifts[b - 1]
            np_ += 2
    if np_ == 0:
        return True
    for i, e in enumerate(f.extrema):
        if i == 0 or <double>_item(e, 1) > top:  # Python's max: the first of equals
            top = _item(e, 1)
    guard = threshold + slack * top
    probe = np.empty(np_)
    cdef double[::1] pr = probe
    for i in range(np_):
        pr[i] = picks[i]
    cdef const double[:] lows = f.values(probe)
    for i in range(np_):
        if not lows[i] - value > guard:
            return False
    return True


cdef Py_ssize_t _distinct(double* a, Py_ssize_t n) noexcept nogil:
    """Sort a[0:n] and keep one of each value (sorted(set(...)) of floats without NaN)."""
    cdef Py_ssize_t i, m = 0
    _insertion_sort(a, n)
    for i in range(n):
        if m == 0 or a[i] != a[m - 1]:
            a[m] = a[i]
            m += 1
    return m


# --------------------------------------------------------------- edges._point_roots

cdef dict _JAW_TERMS = {}
"""atan μ and hypot(1, μ) by μ's bit pattern: constants of the physics, not of a part."""


cdef tuple _jaw_terms(double mu):
    """(atan μ, hypot(1, μ)) through numpy (libm's differ), once per μ (bit for bit)."""
    cdef unsigned long long bits = (<unsigned long long*>&mu)[0]
    got = _JAW_TERMS.get(bits)
    if got is None:
        if len(_JAW_TERMS) >= 64:
            _JAW_TERMS.clear()
        got = _JAW_TERMS[bits] = (float(np.arctan(mu)), float(np.hypot(1.0, mu)))
    return got


def point_roots(c, slopes, jaw, levels):
    """edges._point_roots (with its _equations): θ of every threshold crossing on the
    point-like contact cells, in the same order, the same floats (arcsin, arctan and
    hypot through numpy: libm's differ)."""
    if not _ready:
        _init()
    cdef const double[:] rho = c.rho
    cdef const double[:] R = c.R
    cdef const double[:] phi0 = c.phi0
    cdef const double[:] a = c.a
    cdef const double[:] b = c.b
    cdef Py_ssize_t m = rho.shape[0], ns = len(slopes), nl = len(levels), S = 2 * ns, i, e, r, t = 0
    cdef Py_ssize_t E = S + nl + (0 if jaw is None else 2)
    cdef double mu = 0.0, cc = 0.0, beta = 0.0, hyp = 0.0, kv, x, psi
    if jaw is not None:
        mu, cc = jaw
        beta, hyp = _jaw_terms(mu)
    cdef _Buf buf = _Buf(2 * E + ns + nl + m * E)
    cdef double* delta = buf.p
    cdef double* th = buf.p + E  # the slopes ±t, the levels
    cdef double* k = th + S + nl  # (m, E)
    for i in range(ns):
        th[2 * i], th[2 * i + 1] = 1.0 * <double>slopes[i], -1.0 * <double>slopes[i]
    for i in range(nl):
        th[S + i] = levels[i]
    for e in range(E):
        delta[e] = 0.0 if e < S else (-PI / 2 if e < S + nl else (beta if e == S + nl else -beta))
    clipped = np.empty((m, E))
    cdef double[:, :] cl = clipped
    for i in range(m):
        for e in range(E):
            if e < S:
                kv = th[e] / rho[i]
            elif e < S + nl:
                kv = (th[e] - R[i]) / rho[i]
            elif e == S + nl:
                kv = (mu * R[i] + cc) / (rho[i] * hyp)
            else:
                kv = -k[i * E + e - 1]
            k[i * E + e] = kv
            cl[i, e] = _min(_max(kv, -1.0), 1.0)
    cdef const double[:, :] s = np.arcsin(clipped)
    out = np.empty(2 * m * E)
    cdef double[:] o = out
    for i in range(m):
        for e in range(E):
            if not fabs(k[i * E + e]) <= 1.0:
                continue
            for r in range(2):
                x = delta[e] + s[i, e] if r == 0 else delta[e] + PI - s[i, e]
                psi = phi0[i] + x
                psi = a[i] + _mod(psi - a[i], TWO_PI)  # the root in [a, a + 2π)
                if psi < b[i]:
                    o[t] = HALF_PI - psi
                    t += 1
    return out[:t]
