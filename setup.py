"""The optional compiled kernels (algrasp/planning/_kernels.pyx; everything else is in
pyproject.toml). ``optional=True``: without a compiler the package installs and runs on
its numpy path (algrasp.compiled)."""

from Cython.Build import cythonize
from setuptools import Extension, setup

# -ffp-contract=off: no fused multiply-adds, so every product rounds as numpy's does.
KERNELS = Extension("algrasp.planning._kernels", ["algrasp/planning/_kernels.pyx"],
                    extra_compile_args=["-O2", "-ffp-contract=off", "-fno-fast-math"], optional=True)

setup(ext_modules=cythonize([KERNELS], compiler_directives={"language_level": "3"}, quiet=True))
