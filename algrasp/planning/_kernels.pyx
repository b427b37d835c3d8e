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
from libc.stdlib cimport free, malloc, qsort

from algrasp.planning._floats cimport _bisect_right, _insertion_sort, _max, _min, _mod

from algrasp.planning._lookups import (fixed, images, keys, lifted, lookup, pointwise, rest_zones, shifted,
                                      sink_widths, steps_floats, widest)  # re-exported: one KERNELS

cdef double ROUNDING = 0.0, TWO_PI = 0.0, EDGE_RAD = 0.0, INSIDE = 0.0, SLOPE_NOISE = 0.0
cdef double HALF_PI = np.pi / 2, PI = np.pi
cdef bint _ready = False
cdef object _NONE = None


cdef void _init() except *:
    """The constants of the numpy path, read from it once (it imports this module lazily)."""
    global ROUNDING, TWO_PI, EDGE_RAD, INSIDE, SLOPE_NOISE, _ready, _NONE
    from algrasp.geometry.angles import TWO_PI as two_pi
    from algrasp.geometry.tolerances import ROUNDING as rounding
    from algrasp.planning import setvalued as sv
    ROUNDING, TWO_PI, EDGE_RAD, INSIDE, SLOPE_NOISE = rounding, two_pi, sv.EDGE_RAD, sv._INSIDE, sv.SLOPE_NOISE
    _NONE = sv._NONE
    _ready = True


cdef struct Pair:
    double v
    Py_ssize_t i


cdef int _cmp(const void* a, const void* b) noexcept nogil:
    """By value, then by index: numpy's stable argsort (no NaN here)."""
    cdef const Pair* p = <const Pair*>a
    cdef const Pair* q = <const Pair*>b
    if p.v < q.v:
        return -1
    if p.v > q.v:
        return 1
    return (p.i > q.i) - (p.i < q.i)


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

cdef Py_ssize_t _nodes(const double[:] grid, const double[:] edges, const double[:] kinks, double T,
                       double* x, char* kink) except -1:
    """setvalued._nodes into x, kink (room for every raw node); returns the node count."""
    cdef Py_ssize_t ng = grid.shape[0], ne = edges.shape[0], nk = kinks.shape[0]
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
    qsort(raw, N, sizeof(Pair), _cmp)
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
                    const double* cl, double stall, double eps, double* out_r, double* out_l) noexcept nogil:
    """barriers.barrier_sets for one level ``cl`` (K, n) on rows (2K, 2n) from _rows:
    the farthest right and left barrier of each cell over the copies."""
    cdef Py_ssize_t k, i, j, m = 2 * n
    cdef double level, up, down, e2 = 2.0 * eps, r, lf, best_r, best_l
    cdef const double* row
    for i in range(n):
        up = stall * (x[i + 1] if i < n - 1 else T)
        down = stall * (x[i] + T)
        best_r, best_l = 0.0, 0.0
        for k in range(K):
            level = cl[k * n + i] + up + e2
            row = rows + k * m
            r = INFINITY
            for j in range(i + 1, m):
                if row[j] >= level:
                    r = x[j] + 0.0 if j < n else x[j - n] + T
                    break
            level = cl[((k + 1) % K) * n + i] - down + e2
            row = rows + (K + k) * m
            lf = -INFINITY
            for j in range(n - 1 - i, m):
                if row[j] >= level:  # mirrored index j is node m − 1 − j
                    lf = (x[m - 1 - j] + 0.0 if m - 1 - j < n else x[m - 1 - j - n] + T) - T
                    break
            if k == 0:
                best_r, best_l = r, lf
            else:
                best_r, best_l = _max(best_r, r), _min(best_l, lf)
        out_r[i], out_l[i] = best_r, best_l


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

def classify(f, double T, edges, grid, band, bint first):
    """setvalued._classify's arrays: (x, right, left, rest, barrier_right, barrier_left,
    g (n, 2, K), rims, near), bit-identical to the numpy path."""
    if not _ready:
        _init()
    cdef const double[:] kt = f.kink_thetas
    cdef const double[:] e = edges
    cdef const double[:] gr = grid
    cdef Py_ssize_t N = 1 + gr.shape[0] + 2 * e.shape[0] + kt.shape[0]
    cdef _Buf xb = _Buf(N)
    cdef char* kink = <char*>malloc(N)
    if kink == NULL:
        raise MemoryError()
    try:
        return _classify(f, T, e, gr, kt, band, first, xb.p, kink)
    finally:
        free(kink)


cdef tuple _classify(f, double T, const double[:] e, const double[:] gr, const double[:] kt, band, bint first,
                     double* x, char* kink):
    cdef Py_ssize_t n = _nodes(gr, e, kt, T, x, kink)
    cdef Py_ssize_t K = round(f.period / T), i, j, k, s, t, row, kk, nt
    cdef double stall0 = band.stall[0], stall1 = band.stall[1], sigma = band.sigma
    cdef double jaw = band.jaw_friction, err = band.err, shallow = band.shallow
    cdef double w, gv, vv, a, size, lo_move = stall0 - sigma
    cdef Py_ssize_t* src = <Py_ssize_t*>malloc(n * sizeof(Py_ssize_t))
    if src == NULL:
        raise MemoryError()
    nt = n
    for i in range(n):
        if kink[i]:
            src[i] = nt
            nt += 1
        else:
            src[i] = i
    cdef _Buf tb = _Buf(nt + 3 * nt * K)
    cdef double* base = tb.p
    cdef double* theta = tb.p + nt
    cdef double* gf = theta + nt * K
    cdef double* vf = gf + nt * K
    for i in range(n):  # just inside both ends of every cell; a kink's left limit apart
        w = (x[i + 1] if i < n - 1 else T) - x[i]
        base[i] = x[i] + INSIDE * w
        if kink[i]:
            w = (x[i] if i > 0 else T) - x[i - 1 if i > 0 else n - 1]
            base[src[i]] = x[i] - INSIDE * w
    for t in range(nt):
        for k in range(K):
            theta[t * K + k] = base[t] + (<double>k) * T if K > 1 else base[t]
    try:
        _slopes(f, theta, nt * K, gf, vf)
        x_out = np.empty(n)
        g_out = np.empty((n, 2, K))
        perm = np.zeros((3, n), dtype=np.uint8)
        return _finish(f, T, n, K, x, src, gf, vf, x_out, g_out, perm, stall0, stall1, sigma, jaw, err, shallow, first)
    finally:
        free(src)


cdef tuple _finish(f, double T, Py_ssize_t n, Py_ssize_t K, const double* x, const Py_ssize_t* src, const double* gf,
                   const double* vf, x_out, g_out, perm, double stall0, double stall1, double sigma, double jaw,
                   double err, double shallow, bint first):
    """Permissions, basins and barriers of the sampled cells (setvalued._classify's rest)."""
    cdef double[:] xo = x_out
    cdef double[:, :, :] G = g_out
    cdef unsigned char[:, :] P = perm
    cdef _Buf vb = _Buf(2 * n * K + 2 * K * 2 * n + 4 * n * K + 4 * n)
    cdef double* V = vb.p  # (n, 2, K)
    cdef double* rows = V + 2 * n * K  # (2K, 2n)
    cdef double* nv = rows + 4 * n * K  # (K, n) f at the cells' starts
    cdef double* lv = nv + n * K  # (K, n) a level
    cdef double* br = lv + n * K  # (2, n) barriers of the max level; (2, n) of the min
    cdef Py_ssize_t i, s, k, row, kk
    cdef double gv, vv, a, size, lo_move = stall0 - sigma
    cdef bint movable, either
    for i in range(n):
        xo[i] = x[i]
        for s in range(2):
            row = i if s == 0 else src[i + 1 if i < n - 1 else 0]
            for k in range(K):
                kk = (k + 1) % K if (s == 1 and i == n - 1 and K > 1) else k
                gv, vv = gf[row * K + kk], vf[row * K + kk]
                G[i, s, k] = gv
                V[(i * 2 + s) * K + k] = vv
                a, size = fabs(gv), fabs(vv)
                movable = a > _max(lo_move, SLOPE_NOISE * size)
                either = a <= sigma
                if movable and (gv < 0.0 or either):
                    P[0, i] = 1
                if movable and (gv > 0.0 or either):
                    P[1, i] = 1
                if a <= jaw * size + stall1 + sigma:
                    P[2, i] = 1
    for k in range(K):
        for i in range(n):
            nv[k * n + i] = V[(i * 2) * K + k]
    cdef char* mask = <char*>malloc(n * K)
    if mask == NULL:
        raise MemoryError()
    try:
        for i in range(n * K):
            mask[i] = 0
        rims = _basins(nv, n * K, shallow, mask)
        for k in range(K):
            for i in range(n):
                if mask[k * n + i]:
                    P[0, i], P[1, i] = 1, 1
    finally:
        free(mask)
    cdef bint near = first and err > 0.0
    cdef bint final = not (near and rims)
    _rows(x, n, K, T, nv, stall0, rows)
    if final:
        for k in range(K):
            for i in range(n):
                lv[k * n + i] = _max(V[(i * 2) * K + k], V[(i * 2 + 1) * K + k])
        _barriers(x, n, K, T, rows, lv, stall0, err, br, br + n)
    if near:
        for k in range(K):
            for i in range(n):
                lv[k * n + i] = _min(V[(i * 2) * K + k], V[(i * 2 + 1) * K + k])
        _barriers(x, n, K, T, rows, lv, stall0, err, br + 2 * n, br + 3 * n)
    flags = perm.view(np.bool_)
    found = np.empty((4, n))
    cdef double[:, :] fo = found
    for i in range(n):
        fo[0, i], fo[1, i], fo[2, i], fo[3, i] = br[i], br[n + i], br[2 * n + i], br[3 * n + i]
    return (x_out, flags[0], flags[1], flags[2], found[0] if final else _NONE, found[1] if final else _NONE, g_out,
            rims, (found[2], found[3]) if near else None)


# ---------------------------------------------------------------- setcells passes

cdef inline bint _flag(const unsigned char[:] r, const unsigned char[:] lf, const unsigned char[:] st, int q,
                       Py_ssize_t i) noexcept nogil:
    """Row q of setcells' run flags [R, ~L & ~S, L, ~R & ~S] at cell i."""
    if q == 0:
        return r[i] != 0
    if q == 1:
        return lf[i] == 0 and st[i] == 0
    if q == 2:
        return lf[i] != 0
    return r[i] == 0 and st[i] == 0


cdef inline double _at(const double[:] x, Py_ssize_t n, double T, Py_ssize_t j) noexcept nogil:
    """Cells.at: the lifted start of cell j (any integer)."""
    cdef Py_ssize_t i = j % n
    if i < 0:
        i += n
    return x[i] + (<double>((j - i) // n)) * T


def runs(x, double T, R, L, S):
    """setcells.Cells.runs: (4, n) lifted cell starts where the right-movable and forced-
    right runs containing each cell end and the left ones start (setcells._run_bounds
    over three copies, then Cells.at)."""
    cdef const double[:] xv = x
    cdef const unsigned char[:] r = R.view(np.uint8)
    cdef const unsigned char[:] lf = L.view(np.uint8)
    cdef const unsigned char[:] st = S.view(np.uint8)
    cdef Py_ssize_t n = xv.shape[0], t, j
    cdef int q
    out = np.empty((4, n))
    cdef double[:, :] o = out
    for q in range(2):  # the first False at or after each cell, 4n where none
        j = 4 * n
        for t in range(3 * n - 1, n - 1, -1):
            if not _flag(r, lf, st, q, t % n):
                j = t - n
            if t < 2 * n:
                o[q, t - n] = _at(xv, n, T, j)
    for q in range(2, 4):  # the last False at or before each cell, plus one; −4n + 1 where none
        j = -4 * n
        for t in range(2 * n):
            if not _flag(r, lf, st, q, t % n):
                j = t - n
            if t >= n:
                o[q, t - n] = _at(xv, n, T, j + 1)
    return out


def bound_pieces(x, double T, R, L, S, run_right, run_left, cell_runs, barrier_right, barrier_left, double tol):
    """setcells.bounds up to the pieces: the (start, end, value or None) triples of the
    lower and upper functions after setcells._monotone and _tf's merge; None where the
    part may turn without end."""
    cdef const double[:] xv = x
    cdef const unsigned char[:] r = R.view(np.uint8)
    cdef const unsigned char[:] lf = L.view(np.uint8)
    cdef const unsigned char[:] st = S.view(np.uint8)
    cdef const double[:] rr = run_right
    cdef const double[:] rl = run_left
    cdef const double[:, :] ru = cell_runs
    cdef const double[:] b_r = barrier_right
    cdef const double[:] b_l = barrier_left
    cdef Py_ssize_t n = xv.shape[0], i
    cdef _Buf b = _Buf(3 * n)
    cdef double* up = b.p
    cdef double* lo = b.p + n
    cdef double* ends = b.p + 2 * n
    for i in range(n):
        up[i] = _min(rr[i], b_r[i]) if r[i] else (NAN if st[i] else ru[3, i])
        lo[i] = _max(rl[i], b_l[i]) if lf[i] else (NAN if st[i] else ru[1, i])
        if (r[i] and not isfinite(up[i])) or (lf[i] and not isfinite(lo[i])):
            return None
        ends[i] = xv[i + 1] if i < n - 1 else xv[0] + T
    _monotone(&xv[0], ends, up, lo, n, T)
    return _merge(&xv[0], ends, lo, n, tol), _merge(&xv[0], ends, up, n, tol)


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
    cdef list merged = []
    cdef object last_value = 0.0, value
    cdef object p, last
    cdef double start, top, key, k
    cdef Py_ssize_t i, j, n
    for p in pieces:
        if type(p) is not _Piece:  # _item reads tuples' slots unchecked
            raise TypeError(f"canonical: a piece must be a TransferPiece, not {type(p).__name__}")
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


# ------------------------------------------------------ TransferFunction.compose_after

cdef Py_ssize_t _lifted_starts(outer, double a, double b, double** out) except -1:
    """TransferFunction._lifted_starts: every piece start lifted over [a, b] (with a
    period to spare), sorted, into a malloc'd array (the caller frees it)."""
    cdef list starts = outer.starts
    cdef double base = _item(outer.pieces[0], 0), P = outer.period, s
    cdef Py_ssize_t k0 = <Py_ssize_t>floor((a - base) / P) - 1, k1 = <Py_ssize_t>ceil((b - base) / P) + 1
    cdef Py_ssize_t ns = len(starts), n = (k1 - k0 + 1) * ns, i, k, t = 0
    cdef double* c = <double*>malloc(max(n, 1) * sizeof(double))
    if c == NULL:
        raise MemoryError()
    for k in range(k0, k1 + 1):
        for i in range(ns):
            c[t] = <double>starts[i] + (<double>k) * P
            t += 1
    _insertion_sort(c, n)  # the copies are sorted runs
    out[0] = c
    return n


def compose(outer, inner, double tol_rad):
    """TransferFunction.compose_after's pieces (outer ∘ inner, canonical), the same
    floats: inner's steps read outer at their values, its ramps cut at outer's lifted
    starts and read at each cell's middle."""
    cdef list cells_a = [], cells_b = [], steps = [], probes = []
    cdef double* cuts = NULL
    cdef Py_ssize_t nc = 0, i, j, q
    cdef double ps, pe, lo, hi, c, prev
    _pieces_ready()
    pieces = inner.pieces
    if any(type(p) is not _Piece for p in pieces) or type(outer.pieces[0]) is not _Piece:
        raise TypeError("compose: pieces must be TransferPieces")  # _item reads tuples' slots unchecked
    try:
        for p in pieces:
            v = _item(p, 2)
            if v is not None:
                cells_a.append(_item(p, 0))
                cells_b.append(_item(p, 1))
                steps.append(True)
                probes.append(v)
                continue
            if cuts == NULL:
                lo, hi = _item(pieces[0], 0), _item(pieces[0], 1)
                for pq in pieces:
                    lo = _min_py(lo, _item(pq, 0))
                    hi = _max_py(hi, _item(pq, 1))
                nc = _lifted_starts(outer, lo, hi, &cuts)
            ps, pe = _item(p, 0), _item(p, 1)
            i, j = _bisect_right(cuts, nc, ps), _bisect_right(cuts, nc, pe)
            prev = ps
            for q in range(i, j + 1):
                if q < j:
                    c = cuts[q]
                    if not (ps < c < pe):
                        continue
                else:
                    c = pe
                cells_a.append(prev)
                cells_b.append(c)
                steps.append(False)
                probes.append(0.5 * (prev + c))  # the middle: no rounding at boundaries
                prev = c
    finally:
        free(cuts)
    values = _values_at(outer, probes)
    cdef list out = []
    for i in range(len(probes)):
        v = values[i]
        out.append(_piece(cells_a[i], cells_b[i], (probes[i] if steps[i] else None) if v != v else v))
    return canonical(out, inner.period, tol_rad)


cdef inline double _min_py(double a, double b) noexcept nogil:
    """Python's min(a, b) of floats (the first of equals)."""
    return b if b < a else a


cdef inline double _max_py(double a, double b) noexcept nogil:
    """Python's max(a, b) of floats (the first of equals)."""
    return b if b > a else a


cdef list _values_at(outer, list thetas):
    """TransferFunction.values_at: plain floats for up to FEW_PROBES θ (here), else its
    vectorised pass."""
    cdef Py_ssize_t m = len(thetas), i, n, at
    if m > 16:
        return outer.values_at(thetas)
    first, cuts, after = outer._floats
    cdef double f0 = first, P = outer.period, t, off
    cdef list cl = cuts
    n = len(cl)
    cdef double* c = <double*>malloc(max(n, 1) * sizeof(double))
    if c == NULL:
        raise MemoryError()
    for i in range(n):
        c[i] = cl[i]
    cdef list out = []
    try:
        for i in range(m):
            t = thetas[i]
            off = (floor((t - f0) / P) + 0.0) * P
            at = _bisect_right(c, n, t - off)
            out.append(<double>after[at if at > 1 else 1] + off)
    finally:
        free(c)
    return out


# --------------------------------------------------------------- edges._point_roots

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
        beta, hyp = float(np.arctan(mu)), float(np.hypot(1.0, mu))
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
