"""Importing the package from an interpreter it was not built for names the one it was built for."""

import subprocess
import sys

import penumbra
from penumbra import _built_for


def test_built_for_names_this_interpreter():
    # CTest runs the suite with the interpreter CMake built the module for.
    assert _built_for.PYTHON_VERSION.startswith(f"{sys.version_info.major}.{sys.version_info.minor}")
    assert _built_for.INTERPRETER


def test_import_without_numpy_names_the_interpreter():
    # An interpreter without numpy (a pyenv python3 before Debian's on PATH)
    # gets an ImportError naming the interpreter the module was built for.
    code = "import sys; sys.modules['numpy'] = None; import penumbra"
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert run.returncode != 0
    last = run.stderr.strip().splitlines()[-1]
    assert last.startswith("ImportError: penumbra was built for " + _built_for.INTERPRETER), last
    assert "numpy" in last
    assert penumbra.__version__
