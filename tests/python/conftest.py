"""Fixtures of the Python module's tests: the data folder, the `surftrace` program (the oracle
the module must agree with, bit for bit) and a helper that runs it.

ctest (tests/CMakeLists.txt, test python_module) sets PYTHONPATH to the built module and
SURFTRACE_TOOL to the program; run by hand from the repository root:

    PYTHONPATH=build/ci/python SURFTRACE_TOOL=build/ci/tools/surftrace /usr/bin/python3 -m pytest -q tests/python
"""
import json
import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def data() -> pathlib.Path:
    return pathlib.Path(os.environ.get("SURFTRACE_TEST_DATA", ROOT / "tests" / "data"))


@pytest.fixture(scope="session")
def tool() -> str:
    path = os.environ.get("SURFTRACE_TOOL", str(ROOT / "build" / "ci" / "tools" / "surftrace"))
    if not os.access(path, os.X_OK):
        pytest.fail(f"the surftrace program {path} is missing: build it, or set SURFTRACE_TOOL")
    return path


@pytest.fixture(scope="session")
def run_tool(tool):
    """Runs `surftrace ARGS...`; returns its standard output, parsed as JSON when asked."""

    def run(*args, parse_json=False):
        done = subprocess.run([tool, *map(str, args)], capture_output=True, text=True)
        assert done.returncode == 0, f"surftrace {' '.join(map(str, args))}: {done.stderr}"
        return json.loads(done.stdout) if parse_json else done.stdout

    return run
