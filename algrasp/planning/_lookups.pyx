# cython: language_level=3, boundscheck=False, wraparound=False, cdivision=True, initializedcheck=False
"""Typed loops for transfer-function lookups and what is made of them, bit-identical to
their numpy / plain-float reference: :mod:`algrasp.planning.transfer`'s lookups and lifted
pieces, :mod:`algrasp.planning.placement`'s shifts and pointwise extremes,
:mod:`algrasp.planning.planner`'s keys, fixed tables, widest fits, sink widths and images,
:mod:`algrasp.planning.setcells`' rest zones. The same IEEE operations in the same order
(built with -ffp-contract=off; numpy's maximum, argmax, index −1 and round written out with
its rules; searchsorted as bisection; sets as "the first of equal values kept").
Re-exported by :mod:`algrasp.planning._kernels`, used through :mod:`algrasp.compiled`
only. Radians throughout; O(m log n) for m θ and n pieces.
"""

import numpy as np

from libc.math cimport fabs, floor, isnan, rint, INFINITY, M_PI, NAN
from libc.stdlib cimport free, malloc
from cpython.float cimport PyFloat_AS_DOUBLE
from cpython.list cimport PyList_GET_ITEM, PyList_GET_SIZE
from cpython.tuple cimport PyTuple_GET_ITEM

from algrasp._floats cimport _add_distinct, _bisect_left, _bisect_right, _insertion_sort, _mod

cdef Py_ssize_t LIFTS_LO = -1, LIFTS_HI = 4  # transfer.LIFTS: checked against it at first use
cdef bint _ready = False


cdef void _check() except *:
    global _ready
    from algrasp.planning.transfer import LIFTS
    if (LIFTS.start, LIFTS.stop, LIFTS.step) != (LIFTS_LO, LIFTS_HI, 1):
        raise RuntimeError("_lookups: transfer.LIFTS changed; rebuild the kernels")
    _ready = True


cdef int _table(F, double* first, double** starts, double** values, Py_ssize_t* n) except -1:
    """F._floats in C, read from the pieces (the same floats): the first start, the piece
    starts and [last, *values], NaN on ramps (the caller frees both arrays)."""
    cdef tuple pieces = F.pieces
    cdef Py_ssize_t m = len(pieces), i
    if m == 0:
        raise IndexError("list index out of range")
    for p in pieces:
        if not isinstance(p, tuple) or len(p) != 3:  # slots read unchecked below
            raise TypeError("lookup: pieces must be TransferPieces")
    cdef double* s = <double*>malloc(m * sizeof(double))
    cdef double* v = <double*>malloc((m + 1) * sizeof(double))
    if s == NULL or v == NULL:
        free(s)
        free(v)
        raise MemoryError()
    for i in range(m):
        p = <object>PyTuple_GET_ITEM(pieces, i)
        s[i] = <double>(<object>PyTuple_GET_ITEM(p, 0))
        val = <object>PyTuple_GET_ITEM(p, 2)
        v[i + 1] = NAN if val is None else <double>val
    v[0] = v[m]
    first[0], starts[0], values[0], n[0] = s[0], s, v, m
    return 0


def lookup(F, const double[:] thetas, bint apply):
    """TransferFunction._lookup of a 1-d θ array: (k·P, step values, NaN on ramps); with
    ``apply``, apply_on_ramp's (F(θ), on-ramp flags) from it."""
    cdef double first, P = F.period, kP, v, t
    cdef double* starts = NULL
    cdef double* values = NULL
    cdef Py_ssize_t n, i, m = thetas.shape[0]
    _table(F, &first, &starts, &values, &n)
    a = np.empty(m)
    b = np.empty(m) if not apply else np.empty(m, dtype=np.bool_)
    cdef double[:] out = a
    cdef double[:] vals
    cdef unsigned char[:] ramp
    if apply:
        ramp = b.view(np.uint8)
    else:
        vals = b
    try:
        for i in range(m):
            t = thetas[i]
            kP = floor((t - first) / P) * P
            v = values[_bisect_right(starts, n, t - kP)]
            if apply:
                out[i] = t if isnan(v) else kP + v
                ramp[i] = isnan(v)
            else:
                out[i], vals[i] = kP, v
    finally:
        free(starts)
        free(values)
    return a, b


def steps_floats(F, thetas):
    """TransferFunction.steps_floats: per θ the lifted value of the step holding it, NaN
    on a ramp (C floor keeps np.floor's −0.0 as the Python path does by hand)."""
    cdef double first, P = F.period, q, kP, t
    cdef double* starts = NULL
    cdef double* values = NULL
    cdef Py_ssize_t n
    _table(F, &first, &starts, &values, &n)
    cdef list out = []
    try:
        for x in thetas:
            t = x
            q = (t - first) / P
            kP = floor(q) * P
            out.append(kP + values[_bisect_right(starts, n, t - kP)])
    finally:
        free(starts)
        free(values)
    return out


def lifted(F):
    """TransferFunction.lifted: starts, ends, values (a ramp's is its start) and ramp flags
    over the periods LIFTS, period by period, as read-only arrays (5n,)."""
    if not _ready:
        _check()
    cdef tuple pieces = F.pieces
    cdef Py_ssize_t n = len(pieces), k, i, j, q
    cdef double P = F.period, off
    for p in pieces:
        if not isinstance(p, tuple) or len(p) != 3:  # slots read unchecked below
            raise TypeError("lifted: pieces must be TransferPieces")
    s_, e_, v_ = np.empty(5 * n), np.empty(5 * n), np.empty(5 * n)
    r_ = np.empty(5 * n, dtype=np.bool_)
    cdef double[:] S = s_, E = e_, V = v_
    cdef unsigned char[:] R = r_.view(np.uint8)
    j = (0 - LIFTS_LO) * n  # the unlifted row (k = 0), then every k from it
    for i in range(n):
        p = <object>PyTuple_GET_ITEM(pieces, i)
        val = <object>PyTuple_GET_ITEM(p, 2)
        S[j + i] = <double>(<object>PyTuple_GET_ITEM(p, 0))
        E[j + i] = <double>(<object>PyTuple_GET_ITEM(p, 1))
        V[j + i] = S[j + i] if val is None else <double>val
        R[j + i] = val is None
    for k in (*range(LIFTS_LO, 0), *range(1, LIFTS_HI), 0):  # k = 0 last: in place
        off = (<double>k) * P  # np.arange(...) * P: the int made a double, times P
        for i in range(j, j + n):
            q = i + k * n
            S[q], E[q], V[q], R[q] = S[i] + off, E[i] + off, V[i] + off, R[i]
    for a in (s_, e_, v_, r_):
        a.flags.writeable = False
    return s_, e_, v_, r_


def keys(const double[:] starts, const double[:] values, ramp, double strict):
    """planner._Pieces.of's keys: np.maximum.accumulate(np.where(ramp, starts, values +
    strict)), numpy's maximum (a ≥ b or a NaN: a) running left to right."""
    cdef Py_ssize_t i, m = starts.shape[0]
    cdef const unsigned char[:] r = ramp.view(np.uint8)  # a bool array
    out_ = np.empty(m)
    cdef double[:] out = out_
    cdef double acc = 0.0, x
    for i in range(m):
        x = starts[i] if r[i] else values[i] + strict
        acc = x if i == 0 else (acc if (acc >= x or isnan(acc)) else x)
        out[i] = acc
    return out_


# ----------------------------------------------------------------- placement.pointwise

cdef object _Piece = None


cdef inline object _piece(double a, double b, object v):
    """TransferPiece(a, b, v), as its own __new__ makes it (tuple.__new__)."""
    return tuple.__new__(_Piece, (a, b, v))


cdef Py_ssize_t _cuts(list fs, double a, double P, double* out) noexcept:
    """placement._cuts into ``out`` (room for 2 + every piece): the first of equal values
    kept, as the set does; sorted, in [a, a + P]."""
    cdef Py_ssize_t n = 0, i, j
    cdef double x
    cdef tuple pieces
    out[0], out[1], n = a, a + P, (2 if a + P != a else 1)
    for F in fs:
        pieces = F.pieces
        for i in range(len(pieces)):
            x = <double>(<object>PyTuple_GET_ITEM(<object>PyTuple_GET_ITEM(pieces, i), 0))
            n = _add_distinct(out, n, a + _mod(x - a, P))
    j = 0
    for i in range(n):  # kept in [a, a + P], then an insertion sort (distinct values)
        if a <= out[i] <= a + P:
            out[j] = out[i]
            j += 1
    _insertion_sort(out, j)
    return j


cdef void _steps(F, const double* mids, Py_ssize_t m, double* out, Py_ssize_t stride) except *:
    """steps_floats(F, mids) into out[0], out[stride], …"""
    cdef double first, P = F.period, kP, t
    cdef double* starts = NULL
    cdef double* values = NULL
    cdef Py_ssize_t n, i
    _table(F, &first, &starts, &values, &n)
    for i in range(m):
        t = mids[i]
        kP = floor((t - first) / P) * P
        out[i * stride] = kP + values[_bisect_right(starts, n, t - kP)]
    free(starts)
    free(values)


def shifted(F, double d):
    """[p.shifted(d) for p in F.pieces] (placement.shifted's, before canonical)."""
    _piece_type()
    cdef list out = []
    for p in F.pieces:
        if type(p) is not _Piece:  # slots read unchecked
            raise TypeError("shifted: pieces must be TransferPieces")
        v = <object>PyTuple_GET_ITEM(p, 2)
        out.append(_piece(<double>(<object>PyTuple_GET_ITEM(p, 0)) + d, <double>(<object>PyTuple_GET_ITEM(p, 1)) + d,
                          None if v is None else <double>v + d))
    return out


cdef void _piece_type() except *:
    global _Piece
    if _Piece is None:
        from algrasp.planning.transfer import TransferPiece
        _Piece = TransferPiece


def pointwise(list fs, bint take_max):
    """placement.pointwise's pieces before canonical: the min (or max) of the functions
    cell by cell between their breakpoints, split where the identity crosses the extreme
    constant; the same floats."""
    _piece_type()
    F0 = fs[0]
    cdef double P = F0.period, a = F0.pieces[0].start, c, v, lo, hi
    cdef Py_ssize_t total = 2, nc, nf = 0, i, k, ncell = 0, nconst
    cdef list live = []
    for F in fs:
        total += len(F.pieces)
        if any(not isinstance(p, tuple) or len(p) != 3 for p in F.pieces):  # slots read unchecked
            raise TypeError("pointwise: pieces must be TransferPieces")
        if len(F.pieces) > 1 or F.pieces[0].value is not None:  # the identity: a ramp everywhere
            live.append(F)
    cdef bint ramp_always = len(live) < len(fs), ramp
    cdef double* cuts = <double*>malloc(total * sizeof(double))
    cdef double* mids = <double*>malloc(total * sizeof(double))
    cdef double* ends = <double*>malloc(total * sizeof(double))
    cdef double* vals = <double*>malloc(max(total * len(live), 1) * sizeof(double))
    cdef list out = []
    try:
        if cuts == NULL or mids == NULL or ends == NULL or vals == NULL:
            raise MemoryError()
        nc = _cuts(fs, a, P, cuts)
        for i in range(nc - 1):
            if cuts[i + 1] - cuts[i] > 0.0:
                mids[ncell], ends[ncell] = 0.5 * (cuts[i] + cuts[i + 1]), cuts[i + 1]
                cuts[ncell] = cuts[i]  # (ncell ≤ i: read before written)
                ncell += 1
        nf = len(live)
        for k in range(nf):
            _steps(live[k], mids, ncell, vals + k, nf)
        for i in range(ncell):
            lo, hi = cuts[i], ends[i]
            nconst = 0
            for k in range(nf):
                v = vals[i * nf + k]
                if v == v:
                    if nconst == 0 or (v > c if take_max else v < c):  # max/min: the first of equals
                        c = v
                    nconst += 1
            ramp = ramp_always or nconst < nf
            if nconst == 0:
                out.append(_piece(lo, hi, None))
            elif not ramp or (c >= hi if take_max else c <= lo):
                out.append(_piece(lo, hi, c))
            elif (c <= lo) if take_max else (c >= hi):
                out.append(_piece(lo, hi, None))
            elif take_max:
                out += [_piece(lo, c, c), _piece(c, hi, None)]
            else:
                out += [_piece(lo, c, None), _piece(c, hi, c)]
    finally:
        free(cuts)
        free(mids)
        free(ends)
        free(vals)
    return out


# ------------------------------------------------------------------- planner._widest

cdef inline Py_ssize_t _left(const double[:] a, double x) noexcept nogil:
    """searchsorted(side="left") on a sorted array."""
    return _bisect_left(&a[0], a.shape[0], x) if a.shape[0] else 0


cdef inline Py_ssize_t _right(const double[:] a, double x) noexcept nogil:
    """searchsorted(side="right") on a sorted array."""
    return _bisect_right(&a[0], a.shape[0], x) if a.shape[0] else 0


cdef inline Py_ssize_t _wrap(Py_ssize_t i, Py_ssize_t n) noexcept nogil:
    """numpy's index −1: the last."""
    return i + n if i < 0 else i


def widest(const double[:] starts, const double[:] ramp_starts, const double[:] ramp_ends, const double[:] tops,
           const double[:] at_starts, lower, upper, double room):
    """planner._widest after _fixed: the top-right candidates inside ramps (tops a ramp's
    box reaches), each left end's right end, the first widest; the same floats."""
    cdef Widest w = Widest(lower, upper, starts.shape[0], ramp_starts.shape[0], tops.shape[0])
    cdef Py_ssize_t i
    for i in range(w.ns):
        w.starts[i], w.at_starts[i] = starts[i], at_starts[i]
    for i in range(w.nr):
        w.ramp_starts[i], w.ramp_ends[i] = ramp_starts[i], ramp_ends[i]
    for i in range(w.nt):
        w.tops[i] = tops[i]
    return w.at(room)


cdef class Widest:
    """:func:`widest` for one function and lifting with :func:`fixed`'s arrays made once,
    in C (:meth:`of`): each box height costs one call (A′ asks for several: every sink
    width, every interval), and no array is made."""

    cdef double* buf
    cdef double* starts
    cdef double* at_starts
    cdef double* ramp_starts
    cdef double* ramp_ends
    cdef double* tops
    cdef Py_ssize_t ns, nr, nt
    cdef const double[:] ls, lv, keys, ue, us
    cdef const unsigned char[:] lr, ur

    def __cinit__(self, lower, upper, Py_ssize_t ns, Py_ssize_t nr, Py_ssize_t nt):
        self.buf = <double*>malloc(max(2 * ns + 2 * nr + nt, 1) * sizeof(double))
        if self.buf == NULL:
            raise MemoryError()
        self.starts, self.at_starts = self.buf, self.buf + ns
        self.ramp_starts, self.ramp_ends, self.tops = self.buf + 2 * ns, self.buf + 2 * ns + nr, self.buf + 2 * ns + 2 * nr
        self.ns, self.nr, self.nt = ns, nr, nt
        self.ls, self.lv, self.keys, self.ue, self.us = lower.starts, lower.values, upper.keys, upper.ends, upper.starts
        self.lr, self.ur = lower.ramp.view(np.uint8), upper.ramp.view(np.uint8)

    def __dealloc__(self):
        free(self.buf)

    @staticmethod
    def of(double base, double period, lower, upper, double rounding):
        """The table of :func:`fixed`'s arrays (the same floats), made in C."""
        cdef const double[:] ls = lower.starts, le = lower.ends, lv = lower.values, uv = upper.values
        cdef const unsigned char[:] lr = lower.ramp.view(np.uint8)
        cdef Py_ssize_t n = ls.shape[0], i, ns = 0, nr = 0
        cdef double lo = base - rounding, hi = base + period - rounding
        for i in range(n):
            if ls[i] >= lo and ls[i] < hi:
                ns += 1
                nr += lr[i] != 0
        cdef Widest w = Widest(lower, upper, ns, nr, uv.shape[0])
        ns = nr = 0
        for i in range(n):
            if ls[i] >= lo and ls[i] < hi:
                w.starts[ns] = ls[i]
                w.at_starts[ns] = _value_at(ls, lr, lv, ls[i])
                ns += 1
                if lr[i]:
                    w.ramp_starts[nr], w.ramp_ends[nr] = ls[i], le[i]
                    nr += 1
        w.nt = _distinct_into(uv, w.tops)
        return w

    def at(self, double room):
        """The widest [a, b) whose image fits a box of height ``room`` (planner._widest)."""
        cdef const double[:] ls = self.ls, lv = self.lv, keys = self.keys, ue = self.ue, us = self.us
        cdef const unsigned char[:] lr = self.lr, ur = self.ur
        cdef Py_ssize_t ns = self.ns, nr = self.nr, nt = self.nt, t, k, i, j, c, d
        cdef Py_ssize_t n = ns + (nt if nr else 0)
        cdef double x, y, at, b, w, mw = 0.0, bb = 0.0, bx = 0.0
        cdef bint found = False
        cdef Py_ssize_t* lo = <Py_ssize_t*>malloc(max(2 * nr, 1) * sizeof(Py_ssize_t))
        if lo == NULL:
            raise MemoryError()
        for k in range(nr):  # _ramp_candidates' lo and hi (sorted: the ramps are)
            lo[k] = _bisect_left(self.tops, nt, self.ramp_starts[k] + room)
            lo[nr + k] = _bisect_left(self.tops, nt, self.ramp_ends[k] + room)
        try:
            for i in range(n):
                if i < ns:
                    x, at = self.starts[i], self.at_starts[i]
                else:  # tops[t] − room where more ranges start than end by t
                    t = i - ns
                    c = d = 0
                    for k in range(nr):
                        c += lo[k] <= t
                        d += lo[nr + k] <= t
                    if not c > d:
                        continue
                    x = self.tops[t] - room
                    j = _wrap(_right(ls, x) - 1, ls.shape[0])
                    at = x if lr[j] else lv[j]
                y = at + room
                j = _left(keys, y)
                if j >= us.shape[0]:
                    raise IndexError(f"index {j} is out of bounds for axis 0 with size {us.shape[0]}")
                k = _wrap(j - 1, us.shape[0])
                b = y if (ur[k] and ue[k] > y) else us[j]
                w = b - x
                if not found or (not isnan(mw) and not (w <= mw)):  # argmax: the first maximum, a NaN first
                    found, mw, bb, bx = True, w, b, x
        finally:
            free(lo)
        if not found:
            raise ValueError("attempt to get argmax of an empty sequence")
        return float(bx), float(bb)


# ------------------------------------------------------------------ setcells.rest_zones

def rest_zones(const double[:] nodes, double T, rest, double P, Py_ssize_t K):
    """setcells.rest_zones with K = round(P / T) copies: the maximal rest zones, the one
    through 0 starting at the last start (− P); the same floats."""
    cdef const unsigned char[:] r = rest.view(np.uint8)
    cdef Py_ssize_t n = nodes.shape[0], N = n * (K if K > 1 else 1), i, na = 0, nb = 0, nr = 0
    cdef double* x = <double*>malloc(max(3 * N, 1) * sizeof(double))
    if x == NULL:
        raise MemoryError()
    cdef double* a = x + N
    cdef double* b = x + 2 * N
    cdef list out = []
    try:
        for i in range(N):  # (nodes + k·T for every copy; one copy as it is)
            x[i] = nodes[i % n] + (<double>(i // n)) * T if K > 1 else nodes[i]
            nr += r[i % n] != 0
        if nr == N:
            return ((0.0, P),)
        if nr == 0:
            return ()
        for i in range(N):
            if r[i % n] and not r[(i + N - 1) % N % n]:
                a[na] = x[i]
                na += 1
            if r[i % n] and not r[(i + 1) % N % n]:
                b[nb] = x[i + 1] if i + 1 < N else P
                nb += 1
        if r[0] and r[(N - 1) % n]:  # the zone through 0: from the last start to the first end
            a[na - 1] -= P
            for i in range(na):
                out.append((a[i], b[(i + 1) % nb]))
        else:
            for i in range(min(na, nb)):
                out.append((a[i], b[i]))
    finally:
        free(x)
    return tuple(out)


# -------------------------------------------------------------------- planner._fixed

cdef inline double _value_at(const double[:] ls, const unsigned char[:] lr, const double[:] lv, double x) noexcept nogil:
    """Lifted.value_at of one θ: the lower bound's piece holding it (numpy's index −1: the last)."""
    cdef Py_ssize_t j = _wrap(_right(ls, x) - 1, ls.shape[0])
    return x if lr[j] else lv[j]


cdef object _distinct(const double[:] a):
    """planner._unique: np.array(sorted(set(a.tolist()))) (the first of equal values kept)."""
    out_ = np.empty(a.shape[0])
    cdef double[:] out = out_
    cdef Py_ssize_t m = _distinct_into(a, &out[0]) if a.shape[0] else 0
    return out_[:m].copy()


cdef Py_ssize_t _distinct_into(const double[:] a, double* out) noexcept:
    """:func:`_distinct` into ``out`` (room for all of a): the count kept."""
    cdef Py_ssize_t n = a.shape[0], m = 0, i, j
    cdef double x
    for i in range(n):
        x = a[i]
        for j in range(m):
            if out[j] == x:
                break
        else:
            j = m - 1  # an insertion sort as it goes (distinct values)
            while j >= 0 and x < out[j]:
                out[j + 1] = out[j]
                j -= 1
            out[j + 1] = x
            m += 1
    return m


def fixed(double base, double period, lower, upper, double rounding):
    """planner._fixed: the lower bound's piece starts of one period, its ramps' starts and
    ends there, the upper bound's distinct values and the lower bound at those starts."""
    cdef const double[:] ls = lower.starts, le = lower.ends, lv = lower.values
    cdef const unsigned char[:] lr = lower.ramp.view(np.uint8)
    cdef Py_ssize_t n = ls.shape[0], i, k = 0, q = 0
    cdef double lo = base - rounding, hi = base + period - rounding
    s_, a_, rs_, re_ = np.empty(n), np.empty(n), np.empty(n), np.empty(n)
    cdef double[:] s = s_, a = a_, rs = rs_, re = re_
    for i in range(n):
        if ls[i] >= lo and ls[i] < hi:
            s[k] = ls[i]
            a[k] = _value_at(ls, lr, lv, ls[i])
            k += 1
            if lr[i]:
                rs[q], re[q] = ls[i], le[i]
                q += 1
    return s_[:k].copy(), rs_[:q].copy(), re_[:q].copy(), _distinct(upper.values), a_[:k].copy()


# --------------------------------------------------------------- planner._sink_widths

def sink_widths(lower_F, upper_F, lower, double max_rad, Py_ssize_t max_sinks):
    """planner._sink_widths: upper(x) − lower(x) at every piece start of both bounds, those
    in [0, max_rad] rounded to 10 decimals as numpy's round does (× 1e10, rint, ÷ 1e10),
    distinct and sorted, the ``max_sinks`` smallest; the same floats."""
    cdef const double[:] ls = lower.starts, lv = lower.values
    cdef const unsigned char[:] lr = lower.ramp.view(np.uint8)
    cdef double first, P = upper_F.period, kP, v, x, w
    cdef double* starts = NULL
    cdef double* values = NULL
    cdef Py_ssize_t n, i, m = 0
    xs = [p.start for p in lower_F.pieces] + [p.start for p in upper_F.pieces]
    _table(upper_F, &first, &starts, &values, &n)
    ws_ = np.empty(len(xs))
    cdef double[:] ws = ws_
    try:
        for x in xs:
            kP = floor((x - first) / P) * P
            v = values[_bisect_right(starts, n, x - kP)]
            w = (x if isnan(v) else kP + v) - _value_at(ls, lr, lv, x)
            if w >= 0.0 and w <= max_rad:
                ws[m] = rint(w * 1e10) / 1e10
                m += 1
    finally:
        free(starts)
        free(values)
    return _distinct(ws_[:m])[:max_sinks].tolist()


# ------------------------------------------------------------------- planner.images

def images(lower, upper, list intervals):
    """planner.images after the lifting: [lower(a), upper(b⁻)] of each [a, b) (numpy's
    index −1: the last piece); the same floats."""
    cdef const double[:] ls = lower.starts, lv = lower.values, us = upper.starts, uv = upper.values
    cdef const unsigned char[:] lr = lower.ramp.view(np.uint8), ur = upper.ramp.view(np.uint8)
    cdef double a, b
    cdef Py_ssize_t j
    cdef list out = []
    for pair in intervals:
        a, b = pair
        j = _wrap(_left(us, b) - 1, us.shape[0])
        out.append((_value_at(ls, lr, lv, a), b if ur[j] else uv[j]))
    return out


# ------------------------------------------------------------- verification.verify_set

cdef struct _Fn:
    double first, P, kP  # kP: the last lookup's lift
    double* starts
    double* values  # [last, *values], NaN on ramps (_table's)
    Py_ssize_t n, hint  # hint: the last insertion point


cdef inline Py_ssize_t _piece_of(_Fn* f, double t) noexcept nogil:
    """The lookup of one θ: its lift into f.kP and its insertion point, the last one kept
    while it still is one (starts[i − 1] ≤ x < starts[i]: in a sorted array the count of
    starts ≤ x, which bisect_right returns), else searched."""
    f.kP = floor((t - f.first) / f.P) * f.P
    cdef double x = t - f.kP
    cdef Py_ssize_t i = f.hint
    if not ((i == 0 or f.starts[i - 1] <= x) and (i == f.n or x < f.starts[i])):
        i = f.hint = _bisect_right(f.starts, f.n, x)
    return i


cdef inline double _step_at(_Fn* f, double t) noexcept nogil:
    """apply_on_ramp's F(θ) of one θ (the lookup kernel's: θ itself on a ramp)."""
    cdef double v = f.values[_piece_of(f, t)]
    return t if isnan(v) else f.kP + v


cdef inline bint _same_step(_Fn* f, double t, double kP, Py_ssize_t i) noexcept nogil:
    """Whether θ lies in the piece i under the lift kP (then F(θ) is that step's value)."""
    cdef double k = floor((t - f.first) / f.P) * f.P
    cdef double x = t - k
    return k == kP and (i == 0 or f.starts[i - 1] <= x) and (i == f.n or x < f.starts[i])


cdef Py_ssize_t _second_action(double* lo, double* hi, Py_ssize_t n, Py_ssize_t sorted_to, double a, _Fn* L,
                               _Fn* U) noexcept nogil:
    """The second action over the sample arcs in place, a repeat of the arc before dropped.
    The first ``sorted_to`` samples are points in order (the arc's linspace, clipped and
    shifted: monotone), so where both bounds step (not ramp) at one sample, every later
    sample found in both the same pieces under the same lifts (a prefix, found by
    galloping) maps to the same arc, a repeat: skipped, unevaluated. Returns the count."""
    cdef Py_ssize_t i = 0, q = 0, il, iu, good, bad, j, stride
    cdef double x, y, kl, ku, vl, vu
    while i < n:
        il, iu = _piece_of(L, lo[i] - a), _piece_of(U, hi[i] - a)
        kl, ku, vl, vu = L.kP, U.kP, L.values[il], U.values[iu]
        x = (lo[i] - a if isnan(vl) else kl + vl) + a
        y = (hi[i] - a if isnan(vu) else ku + vu) + a
        if q == 0 or x != lo[q - 1] or y != hi[q - 1]:
            lo[q], hi[q] = x, y
            q += 1
        good = i
        if i < sorted_to and not isnan(vl) and not isnan(vu):
            bad, stride = sorted_to, 1
            while good + stride < sorted_to:  # gallop, then halve: the same pieces are a prefix
                j = good + stride
                if not (_same_step(L, lo[j] - a, kl, il) and _same_step(U, hi[j] - a, ku, iu)):
                    bad = j
                    break
                good, stride = j, 2 * stride
            while bad - good > 1:
                j = (good + bad) >> 1
                if _same_step(L, lo[j] - a, kl, il) and _same_step(U, hi[j] - a, ku, iu):
                    good = j
                else:
                    bad = j
        i = good + 1
    return q


cdef Py_ssize_t _samples_into(double* lo, double* hi, const double[:] starts, double c0, double c1, double T,
                              double a1, Py_ssize_t samples, double probe) noexcept nogil:
    """verification._samples into lo and hi (room for samples + 3·len(starts) + 1): the
    linspace of the arc (numpy's: i·step + c0, the last c1), each piece start's cut inside
    it less the probe, itself, plus the probe, clipped to the arc (numpy's clip keeps an
    end equal to x), shifted by a1; the whole arc last. Returns the count."""
    cdef Py_ssize_t i, j, m = 0, nc = 0, ns = starts.shape[0]
    cdef double delta = c1 - c0, div = <double>(samples - 1), step, x, cut
    step = delta / div if samples > 1 else NAN
    for i in range(samples):
        if samples <= 1:
            x = (<double>i) * delta + c0
        elif step == 0.0:
            x = ((<double>i) / div) * delta + c0
        else:
            x = (<double>i) * step + c0
        lo[m] = x
        m += 1
    if samples > 1:
        lo[m - 1] = c1
    for j in range(3):
        for i in range(ns):
            cut = c0 + _mod(starts[i] - c0, T)
            if cut <= c1:
                lo[m] = cut - probe if j == 0 else (cut if j == 1 else cut + probe)
                m += 1
    for i in range(m):
        x = lo[i]
        x = c0 if x < c0 else x
        x = c1 if x > c1 else x
        lo[i] = hi[i] = x + a1
    lo[m], hi[m] = c0 + a1, c1 + a1
    return m + 1


def verify_arcs(lower, upper, const double[:] starts, double c0, double c1, double T, list angles,
                Py_ssize_t samples, double probe, list want, double bound):
    """verification.verify_set after its outcome check: the sample arcs (:func:`_samples_into`)
    run through the actions after the first (``angles``: every action's gripper angle),
    repeats of the arc before dropped after each; True when every arc ends within
    ``bound`` of a wanted orientation (Python's float remainder, as signed_diff's). The
    same floats as the numpy and plain-float passes it replaces: the verdict is theirs."""
    cdef double x, y, a, m, best, d
    cdef _Fn L, U
    L.starts = L.values = U.starts = U.values = NULL
    L.P, U.P, L.hint, U.hint = lower.period, upper.period, 0, 0
    cdef Py_ssize_t n, i, k, q, total = samples + 3 * starts.shape[0] + 1, nw = len(want)
    cdef bint ok = True
    cdef double* lo = <double*>malloc(2 * total * sizeof(double))
    cdef double* w = <double*>malloc(max(nw, 1) * sizeof(double))
    if lo == NULL or w == NULL:
        free(lo)
        free(w)
        raise MemoryError()
    cdef double* hi = lo + total
    if nw == 0:
        free(lo)
        free(w)
        raise ValueError("min() arg is an empty sequence")
    for i in range(nw):
        w[i] = want[i]
    try:
        _table(lower, &L.first, &L.starts, &L.values, &L.n)
        _table(upper, &U.first, &U.starts, &U.values, &U.n)
        n = _samples_into(lo, hi, starts, c0, c1, T, angles[0], samples, probe)
        for k in range(1, len(angles)):
            a = angles[k]
            if k == 1:
                n = _second_action(lo, hi, n, samples, a, &L, &U)
                continue
            q = 0
            for i in range(n):
                x = _step_at(&L, lo[i] - a) + a
                y = _step_at(&U, hi[i] - a) + a
                if q == 0 or x != lo[q - 1] or y != hi[q - 1]:
                    lo[q], hi[q] = x, y
                    q += 1
            n = q
        for i in range(n):
            m = 0.5 * (lo[i] + hi[i])
            best = INFINITY
            for q in range(nw):
                d = fabs(_mod(m - w[q] + M_PI, 2.0 * M_PI) - M_PI)
                best = d if d < best else best
            if not (best + 0.5 * (hi[i] - lo[i]) <= bound):
                ok = False
                break
    finally:
        free(lo)
        free(w)
        free(L.starts)
        free(L.values)
        free(U.starts)
        free(U.values)
    return ok


# ------------------------------------------------------------- transfer.arcs_holding

cdef void _stable_sort_by(double* key, double* a, Py_ssize_t* b, Py_ssize_t n) noexcept nogil:
    """Sort key[0:n] ascending carrying a and b along (stable, as sorted(key=...) is; an
    insertion sort: the runs it gets are short and nearly sorted)."""
    cdef Py_ssize_t i, j, vb
    cdef double vk, va
    for i in range(1, n):
        vk, va, vb = key[i], a[i], b[i]
        j = i - 1
        while j >= 0 and vk < key[j]:
            key[j + 1], a[j + 1], b[j + 1] = key[j], a[j], b[j]
            j -= 1
        key[j + 1], a[j + 1], b[j + 1] = vk, va, vb


def arcs_holding(list lo, list hi, double T):
    """transfer.arcs_holding's plain-float path: the three lifted copies of the intervals
    shifted into [0, T) (floor keeping −0.0), sorted stably by start, every gap after a
    running reach (numpy's maximum: reach ≥ h keeps reach) in [0, T), the widest first
    (stable); the same floats."""
    cdef Py_ssize_t n = min(len(lo), len(hi)), m = 3 * n, i, k, ng = 0
    cdef double widest = 0.0, w, a, b, shift, reach, h, gap
    if n == 0:
        raise ValueError("max() arg is an empty sequence")
    for i in range(n):  # max(b − a): the first of equals, replaced only by a larger one
        w = <double>hi[i] - <double>lo[i]
        if i == 0 or w > widest:
            widest = w
    if widest >= T:
        return [(0.0, T)]
    cdef double* L = <double*>malloc(5 * m * sizeof(double) + 2 * m * sizeof(Py_ssize_t))
    if L == NULL:
        raise MemoryError()
    cdef double* H = L + m
    cdef double* G = L + 2 * m
    cdef double* R = L + 3 * m
    cdef double* spare = L + 4 * m
    cdef Py_ssize_t* idx = <Py_ssize_t*>(L + 5 * m)
    cdef Py_ssize_t* kk = idx + m
    cdef list out = []
    try:
        for i in range(n):
            a, b = lo[i], hi[i]
            shift = floor(a / T) * T
            a, b = a - shift, b - shift
            L[i], L[n + i], L[2 * n + i] = a - T, a, a + T
            H[i], H[n + i], H[2 * n + i] = b - T, b, b + T
        for i in range(m):
            idx[i] = i
            spare[i] = 0.0
        _stable_sort_by(L, spare, idx, m)
        for i in range(m):
            spare[i] = H[idx[i]]
        reach = -INFINITY
        for k in range(m - 1):
            h = spare[k]
            reach = reach if reach >= h else h
            gap = L[k + 1] - reach
            if 0.0 <= reach < T and gap > 0.0:
                G[ng], R[ng], kk[ng] = -gap, reach, k
                ng += 1
        if ng == 0:
            return [(0.0, T)]
        _stable_sort_by(G, R, kk, ng)
        for i in range(ng):
            out.append((L[kk[i] + 1], R[i] + T))
    finally:
        free(L)
    return out


# ------------------------------------------------------------- planner.first_choice

cdef inline double _shortest_turn(double x, double p) noexcept nogil:
    """angles.shortest_turn: (x + p/2) % p − p/2, Python's float remainder."""
    return _mod(x + p / 2.0, p) - p / 2.0


def first_choice(list arcs, list fit, double need, nxt, double alpha_next, double period, double T,
                 double two_tol):
    """planner.first_choice: of the arcs with room ≥ need, each angle centring it in ``nxt``
    (one per turn mapping the action to itself: T when its room exceeds ``two_tol``, else
    the period; Python's round half to even), the first least (turning, index); the same floats."""
    cdef Py_ssize_t k, i, count, best_k = 0, out_k = 0
    cdef double room, turn, base, alpha, t, r, best_t = 0.0, out_a = 0.0
    cdef double mid = 0.5 * (<double>nxt[0] + <double>nxt[1])
    cdef bint found = False
    for k in range(len(arcs)):
        room = fit[k]
        if not room >= need:
            continue
        arc = arcs[k]
        turn = T if room > two_tol else period
        base = alpha_next + mid - 0.5 * (<double>arc[0] + <double>arc[1])
        r = 2.0 * M_PI / turn
        if isnan(r):
            raise ValueError("cannot convert float NaN to integer")
        if r == INFINITY or r == -INFINITY:
            raise OverflowError("cannot convert float infinity to integer")
        count = <Py_ssize_t>rint(r)
        for i in range(count if count > 1 else 1):
            alpha = base + (<double>i) * turn
            t = fabs(_shortest_turn(alpha, period)) + fabs(_shortest_turn(alpha_next - alpha, period))
            if not found or (k < best_k if t == best_t else t < best_t):
                found, best_t, best_k, out_k, out_a = True, t, k, k, alpha
    if not found:
        raise ValueError("min() arg is an empty sequence")
    return out_k, out_a
