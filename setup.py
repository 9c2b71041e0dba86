"""The compiled parts of the package: VisiLibity1's visibility polygon (C++), built with the package, and then the
engines' numba kernels, compiled into the package (``build_support/build_kernels.py``).

Everything else about the package is in pyproject.toml; this file only declares the extension, which setuptools
cannot yet take from pyproject.toml without an experimental warning. A C++ compiler is needed (g++ or clang++).
"""

import sys
from pathlib import Path

from setuptools import Extension, setup

sys.path.insert(0, str(Path(__file__).resolve().parent / "build_support"))
from build_kernels import BuildExtAndKernels

NATIVE = "omega_prime_visibility/engines/visilibity/native"

setup(
    cmdclass={"build_ext": BuildExtAndKernels},
    ext_modules=[
        Extension(
            "omega_prime_visibility.engines.visilibity._visilibity1",
            sources=[f"{NATIVE}/binding.cpp", f"{NATIVE}/visilibity.cpp"],
            include_dirs=[NATIVE],
            language="c++",
        )
    ],
)
