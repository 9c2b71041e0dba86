"""The compiled part of the package: VisiLibity1's visibility polygon (C++), built with the package.

Everything else about the package is in pyproject.toml; this file only declares the extension, which setuptools
cannot yet take from pyproject.toml without an experimental warning. A C++ compiler is needed (g++ or clang++).
"""

from setuptools import Extension, setup

NATIVE = "omega_prime_visibility/engines/visilibity/native"

setup(
    ext_modules=[
        Extension(
            "omega_prime_visibility.engines.visilibity._visilibity1",
            sources=[f"{NATIVE}/binding.cpp", f"{NATIVE}/visilibity.cpp"],
            include_dirs=[NATIVE],
            language="c++",
        )
    ]
)
