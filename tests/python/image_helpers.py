"""What test_image.py and test_compare.py share: the CLI they are held to, 1CRN's SES, and the
CLI's render of it (an EXR, a PNG and the camera it wrote), made once per session."""
import os
import pathlib
import subprocess

import surftrace

ROOT = pathlib.Path(__file__).resolve().parents[2]
TOOL = os.environ.get("SURFTRACE_TOOL", str(ROOT / "build" / "ci" / "tools" / "surftrace"))
CRAMBIN = ROOT / "tests" / "data" / "structures" / "1crn.pdb"

# Every buffer an Image hands out, as the EXR stores it.
BUFFERS = ("rgb", "alpha", "depth_t", "depth_z", "normal", "patch_kind", "patch_id", "atom_id", "flags",
           "seam_distance")


def ses(path=CRAMBIN):
    """The SES of a structure file."""
    return surftrace.ses(surftrace.read(str(path)))


def cli(*args):
    """Runs the surftrace program; its output when it succeeds."""
    done = subprocess.run([TOOL, *map(str, args)], capture_output=True, text=True)
    assert done.returncode == 0, f"{TOOL} {' '.join(map(str, args))}: {done.stderr}"
    return done.stdout


def cli_render(folder, name, *options):
    """`surftrace render 1crn.pdb` to NAME.exr, NAME.png and NAME.json (its --camera-out)."""
    exr, png, camera = (folder / f"{name}.{ext}" for ext in ("exr", "png", "json"))
    cli("render", CRAMBIN, "--exr", exr, "-o", png, "--camera-out", camera, "--quiet", *options)
    return exr, png, camera


def buffers_equal(a, b):
    """Every buffer of two images equal, element for element (NaN equal to NaN)."""
    import numpy as np

    different = []
    for name in BUFFERS:
        x, y = getattr(a, name), getattr(b, name)
        if x is None or y is None:
            if (x is None) != (y is None):
                different.append(name)
            continue
        equal = x.dtype == y.dtype and np.array_equal(x, y, equal_nan=x.dtype.kind == "f")
        if not equal:
            different.append(name)
    return different
