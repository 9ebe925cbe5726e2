"""`cmake --install` puts the module where Debian's /usr/bin/python3 finds it for the prefix
/usr/local (lib/python3.X/dist-packages), and it imports from there."""
import os
import pathlib
import subprocess
import sys

import pytest


def test_installed_module_imports(tmp_path):
    build, cmake = os.environ.get("SURFTRACE_BUILD_DIR"), os.environ.get("SURFTRACE_CMAKE", "cmake")
    if not build:
        pytest.skip("SURFTRACE_BUILD_DIR is not set (ctest sets it)")
    subprocess.run([cmake, "--install", build, "--prefix", str(tmp_path)], check=True, capture_output=True)
    found = sorted(tmp_path.glob("lib/python3*/*-packages/surftrace*.so"))
    assert len(found) == 1, sorted(str(p) for p in tmp_path.rglob("surftrace*.so"))
    folder = found[0].parent
    # Installed under /usr/local, this is a folder Debian's python3 searches with no variable set.
    searched = subprocess.run([sys.executable, "-c", "import sys; print('\\n'.join(sys.path))"],
                              capture_output=True, text=True, env={"PATH": "/usr/bin:/bin"}).stdout.split()
    assert "/usr/local/" + str(folder.relative_to(tmp_path)) in searched, searched
    env = {"PATH": "/usr/bin:/bin", "PYTHONPATH": str(folder)}
    done = subprocess.run([sys.executable, "-c", "import surftrace; print(surftrace.__file__)"],
                          capture_output=True, text=True, env=env, cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert pathlib.Path(done.stdout.strip()) == found[0]
