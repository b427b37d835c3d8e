# Float helpers shared by the compiled kernels (planning/_kernels.pyx, _lookups.pyx,
# geometry/_geometry.pyx, _polygon.pyx): each
# reproduces, bit for bit, the numpy or Python operation its docstring names. Inline, so
# cimporting them needs no module of their own at run time.

from libc.math cimport copysign, fmod, isnan


cdef inline double _mod(double a, double b) noexcept nogil:
    """numpy's (and Python's) float remainder: the sign of the divisor, +0.0 for none."""
    cdef double m = fmod(a, b)
    if m != 0.0:
        if (b < 0.0) != (m < 0.0):
            m += b
    else:
        m = copysign(0.0, b)
    return m


cdef inline double _max(double a, double b) noexcept nogil:
    """np.maximum(a, b)."""
    return a if (a >= b or isnan(a)) else b


cdef inline double _min(double a, double b) noexcept nogil:
    """np.minimum(a, b)."""
    return a if (a <= b or isnan(a)) else b


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


cdef inline void _insertion_sort(double* a, Py_ssize_t n) noexcept nogil:
    """Sort a[0:n] ascending in place (stable; quick on the nearly sorted runs it gets)."""
    cdef Py_ssize_t i, j
    cdef double v
    for i in range(1, n):
        v = a[i]
        j = i - 1
        while j >= 0 and v < a[j]:
            a[j + 1] = a[j]
            j -= 1
        a[j + 1] = v


cdef inline Py_ssize_t _bisect_left(const double* a, Py_ssize_t n, double x) noexcept nogil:
    """bisect.bisect_left / searchsorted(side="left") on a sorted C array."""
    cdef Py_ssize_t lo = 0, hi = n, mid
    while lo < hi:
        mid = (lo + hi) >> 1
        if a[mid] < x:
            lo = mid + 1
        else:
            hi = mid
    return lo


cdef inline Py_ssize_t _add_distinct(double* out, Py_ssize_t n, double x) noexcept nogil:
    """x appended to out[0:n] unless a value there equals it (a Python set's first of
    equal values kept: −0.0 and 0.0 are one); the new count."""
    cdef Py_ssize_t j
    for j in range(n):
        if out[j] == x:
            return n
    out[n] = x
    return n + 1
