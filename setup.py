"""Builds the penumbra Python package with CMake, for `pip install --no-build-isolation .`.

pip runs this through setuptools' build backend (pyproject.toml). It builds the
module and libpenumbra with CMake for the interpreter running it, installs
them into a scratch prefix, and makes a wheel of the package with the
libraries beside the module (its RPATH holds $ORIGIN for this, and
libpenumbra finds its image module beside itself). No download: CMake finds
what scripts/setup.sh installed.

Environment: PENUMBRA_BUILD_DIR, the CMake build folder (default build-pip/,
kept between installs so a second one is incremental; an existing build of
the project may be named if it was configured for this Python version);
PENUMBRA_CMAKE_ARGS, extra configure arguments (split on spaces);
CMAKE_BUILD_PARALLEL_LEVEL, the build's jobs; CMake reads
CMAKE_CXX_COMPILER_LAUNCHER (ccache) from the environment itself.
"""

import os
import pathlib
import re
import shutil
import subprocess
import sys

from setuptools import Distribution, setup
from setuptools.command.build_py import build_py

SOURCE = pathlib.Path(__file__).resolve().parent
BUILD = pathlib.Path(os.environ.get("PENUMBRA_BUILD_DIR") or SOURCE / "build-pip").resolve()


def configure():
    """Configures BUILD for this interpreter, or checks that its configuration fits it."""
    cache = BUILD / "CMakeCache.txt"
    if cache.exists():
        found = re.search(r"^Python3_EXECUTABLE:[A-Z]+=(.*)$", cache.read_text(), re.M)
        if not found:
            sys.exit(f"{BUILD} was configured without the Python module; name another PENUMBRA_BUILD_DIR")
        theirs = subprocess.run([found.group(1), "-c", "import sys; print(*sys.version_info[:2])"],
                                capture_output=True, text=True).stdout.split()
        if theirs != [str(v) for v in sys.version_info[:2]]:
            sys.exit(f"{BUILD} builds the module for {found.group(1)} (Python {'.'.join(theirs)}), not for "
                     f"{sys.executable}; name another PENUMBRA_BUILD_DIR")
        return
    subprocess.run(["cmake", "-S", str(SOURCE), "-B", str(BUILD), "-DCMAKE_BUILD_TYPE=Release",
                    f"-DPython3_EXECUTABLE={sys.executable}", "-DPENUMBRA_BUILD_TESTS=OFF",
                    "-DPENUMBRA_BUILD_APPS=OFF"] + os.environ.get("PENUMBRA_CMAKE_ARGS", "").split(), check=True)


class CMakeBuildPy(build_py):
    """The package comes from `cmake --install`, not from copying sources."""

    def run(self):
        configure()
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL") or str(os.cpu_count() or 1)
        subprocess.run(["cmake", "--build", str(BUILD), "--target", "penumbra_python", "-j", jobs], check=True)
        stage = BUILD / "pip-stage"
        shutil.rmtree(stage, ignore_errors=True)
        for component in ("Runtime", "Python"):
            subprocess.run(["cmake", "--install", str(BUILD), "--prefix", str(stage), "--component", component],
                           check=True)
        package = next(stage.rglob("penumbra/__init__.py")).parent
        target = pathlib.Path(self.build_lib) / "penumbra"
        shutil.rmtree(target, ignore_errors=True)
        shutil.copytree(package, target)
        # A wheel holds no symbolic links: each library under the name the
        # loader asks for (a soname link becomes the file it names).
        for lib in stage.rglob("libpenumbra*.so*"):
            if lib.is_symlink() or not any(p.is_symlink() and p.resolve() == lib.resolve()
                                           for p in lib.parent.iterdir()):
                shutil.copy2(lib, target / lib.name)
        shutil.rmtree(stage)


class BinaryDistribution(Distribution):
    """A wheel for this interpreter and platform: it holds compiled code."""

    def has_ext_modules(self):
        return True


BUILD.mkdir(parents=True, exist_ok=True)
setup(
    packages=["penumbra"],
    package_dir={"penumbra": "python/penumbra"},
    cmdclass={"build_py": CMakeBuildPy},
    distclass=BinaryDistribution,
    options={"build": {"build_base": str(BUILD / "setuptools")},
             "egg_info": {"egg_base": str(BUILD)}},
)
