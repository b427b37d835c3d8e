"""The optional compiled kernels (algrasp/planning/_kernels.pyx and _lookups.pyx,
algrasp/geometry/_geometry.pyx and _polygon.pyx; everything else is in pyproject.toml).
``optional=True``: without a C compiler (or without Cython, outside build isolation) the
package installs and runs on its numpy path (algrasp.compiled)."""

from setuptools import Extension, setup

# -ffp-contract=off: no fused multiply-adds, so every product rounds as numpy's does.
# (algrasp/_floats.pxd holds inline helpers every kernel cimports: no module of its own.)
EXTENSIONS = [Extension(f"algrasp.{package}.{name}", [f"algrasp/{package}/{name}.pyx"],
                        extra_compile_args=["-O2", "-ffp-contract=off", "-fno-fast-math"], optional=True)
              for package, name in (("planning", "_kernels"), ("planning", "_lookups"),
                                    ("geometry", "_geometry"), ("geometry", "_polygon"))]

try:
    from Cython.Build import cythonize
except ImportError:  # no Cython: no kernels
    modules = []
else:
    modules = cythonize(EXTENSIONS, compiler_directives={"language_level": "3"}, quiet=True)
    for module in modules:  # cythonize's copies drop ``optional``
        module.optional = True

setup(ext_modules=modules)
