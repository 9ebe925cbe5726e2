"""The scripts in examples/python/, run as a user runs them (a subprocess of /usr/bin/python3 with
this environment's PYTHONPATH), on the bundled data; their outcomes checked against the
`surftrace` command line program (conftest.py's run_tool) and the file system."""
import csv as csv_module
import math
import os
import struct
import subprocess
import zlib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples" / "python"
PYTHON = "/usr/bin/python3"


def run_example(name, *args, expect=0):
    result = subprocess.run([PYTHON, str(EXAMPLES / name), *map(str, args)], capture_output=True, text=True,
                            env=os.environ.copy(), cwd=ROOT, timeout=120)
    assert result.returncode == expect, f"{name} exited {result.returncode}:\n{result.stdout}\n{result.stderr}"
    return result.stdout


def png_size(path):
    """(width, height) of a PNG, after checking its signature, every chunk's CRC and that IEND
    ends it, and that its image data inflates."""
    data = Path(path).read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", f"{path} is not a PNG"
    pos, chunks, idat = 8, [], b""
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        (crc,) = struct.unpack(">I", data[pos + 8 + length:pos + 12 + length])
        assert zlib.crc32(kind + body) == crc, f"{path}: bad CRC in chunk {kind}"
        chunks.append(kind)
        if kind == b"IDAT":
            idat += body
        if kind == b"IHDR":
            width, height = struct.unpack(">II", body[:8])
        pos += 12 + length
    assert chunks[0] == b"IHDR" and chunks[-1] == b"IEND", chunks
    assert len(zlib.decompress(idat)) > 0
    return width, height


def test_residue_areas_sum_to_the_total_ses_area(tmp_path, data, run_tool):
    crambin = data / "structures" / "1crn.pdb"
    csv = tmp_path / "residues.csv"
    out = run_example("residue_areas.py", crambin, "--csv", csv)
    with open(csv, newline="") as f:
        residues = list(csv_module.DictReader(f))
    total = run_tool("area", crambin, "--format", "json", parse_json=True)["ses"]["total"]
    assert len(residues) == 46  # crambin's residues
    assert math.isclose(math.fsum(float(r["area"]) for r in residues), total, rel_tol=1e-9, abs_tol=0.0)
    assert len(out.splitlines()) >= 11  # a summary line and the ten largest


def test_adk_trajectory_prints_the_cli_areas_and_plots_them(tmp_path, data, run_tool):
    topology, trajectory = data / "trajectories" / "adk_dims" / "adk.psf.gz", data / "trajectories" / "adk_dims" / "adk_dims.dcd"
    png = tmp_path / "adk.png"
    out = run_example("adk_trajectory.py", topology, trajectory, png, "--frames", 3, "--size", "640x480")
    rows = [line.split() for line in out.splitlines() if line[:1].isdigit()]
    assert [int(r[0]) for r in rows] == [0, 1, 2]
    # Frame 0 is a full build, frames 1 and 2 the Updater's partial ones: each equals the CLI's
    # fresh build of that frame, to the last bit.
    cli = run_tool("area", topology, trajectory, "--frames", "0:3", "--format", "json", parse_json=True)["frames"]
    assert [(float(r[2]), float(r[3])) for r in rows] == [(f["ses"], f["ses_volume"]) for f in cli]
    assert png_size(png) == (640, 480)


def test_validate_depth_passes_a_small_error_and_fails_a_large_one(data):
    crambin = data / "structures" / "1crn.pdb"
    small = run_example("validate_depth.py", crambin, "--error", 0.001)
    assert small.splitlines()[-1].startswith("PASS")
    large = run_example("validate_depth.py", crambin, "--error", 0.5, expect=2)
    assert "FAIL" in large and "depth p99" in large
