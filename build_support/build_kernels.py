"""Building the package compiles its kernels too, so that a fresh install's first call loads them instead of
compiling for a minute or two (issue 52).

Two parts, both used by pip and uv through ``pyproject.toml``'s ``[build-system]``:

- the build backend (this module, ``build-backend = "build_kernels"``): setuptools' own, with the package's runtime
  dependencies added to what a wheel or an editable install needs to build (the kernels are compiled by running
  the engines, which import them; pip and uv install them into the isolated build environment from wheels);
- :class:`BuildExtAndKernels` (setup.py's ``build_ext``): after VisiLibity1's C++ is built, runs
  ``omega-prime-visibility compile`` on the built package, with a private cache, so the compiled kernels land in the
  package's ``_kernels/`` folder (in the wheel, or beside the sources of an editable install).

``OMEGA_PRIME_VISIBILITY_BUILD_KERNELS=0`` builds without them (the Makefile's ``uv sync`` does: ``make run``
compiles in the environment itself); a build whose compiling fails says so and goes on (the kernels are then
compiled at first use, as before).
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import tomllib
from pathlib import Path

from setuptools import build_meta
from setuptools.build_meta import *  # noqa: F403  (every hook setuptools has, some replaced below)
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent.parent
SWITCH = "OMEGA_PRIME_VISIBILITY_BUILD_KERNELS"


def wanted() -> bool:
    """Whether this build compiles the kernels (unless ``OMEGA_PRIME_VISIBILITY_BUILD_KERNELS=0``)."""
    return os.environ.get(SWITCH, "1").strip() not in ("0", "no", "false")


def runtime_dependencies() -> list[str]:
    """The package's dependencies, as ``pyproject.toml`` declares them."""
    with open(ROOT / "pyproject.toml", "rb") as f:
        return list(tomllib.load(f)["project"]["dependencies"])


def get_requires_for_build_wheel(config_settings=None) -> list[str]:
    extra = runtime_dependencies() if wanted() else []
    return [*build_meta.get_requires_for_build_wheel(config_settings), *extra]


def get_requires_for_build_editable(config_settings=None) -> list[str]:
    extra = runtime_dependencies() if wanted() else []
    return [*build_meta.get_requires_for_build_editable(config_settings), *extra]


class BuildExtAndKernels(build_ext):
    """setuptools' ``build_ext``, then the kernels compiled into the built package's ``_kernels/``."""

    def run(self) -> None:
        super().run()
        if not wanted():
            return
        editable = bool(getattr(self, "editable_mode", False) or self.inplace)
        root = ROOT if editable else Path(self.build_lib).resolve()
        compile_kernels(root)


def compile_kernels(root: Path) -> bool:
    """Run ``omega-prime-visibility compile`` on the package under ``root`` with a private cache (what it compiles
    is copied into ``root/omega_prime_visibility/_kernels``); True if it went through."""
    print("compiling the engines' kernels into the package (a minute or two; "
          f"{SWITCH}=0 skips it)", file=sys.stderr, flush=True)  # fmt: skip
    with tempfile.TemporaryDirectory(prefix="omega-prime-visibility-build-") as cache:
        env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
        env |= {
            "XDG_CACHE_HOME": cache,
            "PYTHONPATH": os.pathsep.join(filter(None, [str(root), env.get("PYTHONPATH")])),
        }
        done = subprocess.run(
            [sys.executable, "-m", "omega_prime_visibility.cli", "compile"], env=env, cwd=cache,
            capture_output=True, text=True,
        )  # fmt: skip
    if done.returncode != 0:
        said = (done.stderr or done.stdout).strip().splitlines()[-3:]
        print("the kernels could not be compiled now; they will be at first use:", *said, sep="\n  ", file=sys.stderr)
        return False
    print(done.stdout.strip().splitlines()[-2] if done.stdout.strip() else "compiled", file=sys.stderr)
    return True
