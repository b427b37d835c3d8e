"""The optional compiled kernels (algrasp/planning/_kernels.pyx; everything else is in
pyproject.toml). ``optional=True``: without a C compiler (or without Cython, outside
build isolation) the package installs and runs on its numpy path (algrasp.compiled)."""

from setuptools import Extension, setup

# -ffp-contract=off: no fused multiply-adds, so every product rounds as numpy's does.
KERNELS = Extension("algrasp.planning._kernels", ["algrasp/planning/_kernels.pyx"],
                    extra_compile_args=["-O2", "-ffp-contract=off", "-fno-fast-math"], optional=True)
LOOKUPS = Extension("algrasp.planning._lookups", ["algrasp/planning/_lookups.pyx"],
                    extra_compile_args=["-O2", "-ffp-contract=off", "-fno-fast-math"], optional=True)

try:
    from Cython.Build import cythonize
except ImportError:  # no Cython: no kernels
    modules = []
else:
    modules = cythonize([KERNELS, LOOKUPS], compiler_directives={"language_level": "3"}, quiet=True)
    for module in modules:  # cythonize's copies drop ``optional``
        module.optional = True

setup(ext_modules=modules)
