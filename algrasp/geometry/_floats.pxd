# Float helpers shared by the compiled geometry kernels (_geometry.pyx, _polygon.pyx): each
# reproduces, bit for bit, the Python or numpy operation its docstring names. Inline, so
# cimporting them needs no module of their own at run time.

from libc.math cimport copysign, fmod


cdef inline double _mod(double a, double b) noexcept nogil:
    """Python's float remainder: the sign of the divisor, +0.0 for none."""
    cdef double m = fmod(a, b)
    if m != 0.0:
        if (b < 0.0) != (m < 0.0):
            m += b
    else:
        m = copysign(0.0, b)
    return m


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
