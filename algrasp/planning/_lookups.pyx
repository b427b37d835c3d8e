# cython: language_level=3, boundscheck=False, wraparound=False, cdivision=True, initializedcheck=False
"""Typed loops for transfer-function lookups (:mod:`algrasp.planning.transfer`) and the
lifted pieces A′ searches (:mod:`algrasp.planning.planner`), bit-identical to their
numpy / plain-float reference: the same IEEE operations in the same order (built with
-ffp-contract=off; numpy's maximum written out with its rules; searchsorted(side="right")
as bisect_right). Re-exported by :mod:`algrasp.planning._kernels` and used through
:mod:`algrasp.compiled` only. Radians throughout; O(m log n) for m θ and n pieces.
"""

import numpy as np

from libc.math cimport floor, isnan
from libc.stdlib cimport free, malloc
from cpython.float cimport PyFloat_AS_DOUBLE
from cpython.list cimport PyList_GET_ITEM, PyList_GET_SIZE
from cpython.tuple cimport PyTuple_GET_ITEM

cdef Py_ssize_t LIFTS_LO = -1, LIFTS_HI = 4  # transfer.LIFTS: checked against it at first use
cdef bint _ready = False


cdef void _check() except *:
    global _ready
    from algrasp.planning.transfer import LIFTS
    if (LIFTS.start, LIFTS.stop, LIFTS.step) != (LIFTS_LO, LIFTS_HI, 1):
        raise RuntimeError("_lookups: transfer.LIFTS changed; rebuild the kernels")
    _ready = True


cdef inline Py_ssize_t _bisect_right(const double* a, Py_ssize_t n, double x) noexcept nogil:
    """bisect.bisect_right / searchsorted(side="right") on a sorted C array (a NaN x: n)."""
    cdef Py_ssize_t lo = 0, hi = n, mid
    while lo < hi:
        mid = (lo + hi) >> 1
        if x < a[mid]:
            hi = mid
        else:
            lo = mid + 1
    return lo


cdef double* _doubles(list xs, Py_ssize_t* n) except NULL:
    """A list of floats as a malloc'd C array (the caller frees it)."""
    cdef Py_ssize_t i, m = PyList_GET_SIZE(xs)
    cdef double* out = <double*>malloc(max(m, 1) * sizeof(double))
    if out == NULL:
        raise MemoryError()
    for i in range(m):
        out[i] = <double>(<object>PyList_GET_ITEM(xs, i))
    n[0] = m
    return out


cdef int _table(F, double* first, double** starts, double** values, Py_ssize_t* n) except -1:
    """F._floats (its first start, piece starts and [last, *values], NaN on ramps) in C."""
    f0, st, vals = F._floats
    cdef Py_ssize_t nv
    first[0] = f0
    starts[0] = _doubles(st, n)
    try:
        values[0] = _doubles(vals, &nv)
    except BaseException:
        free(starts[0])
        raise
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
