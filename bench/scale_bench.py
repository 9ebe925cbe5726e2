#!/usr/bin/python3
"""Scale benchmark: 1AON tiled 1, 8 (2x2x2) and 27 (3x3x3) times.

Makes the tiled inputs from the bundled tests/data/paper/1aon.pdb.gz (never stored in the
repository) and measures, per size, the whole `surftrace` process with /usr/bin/time -v:
CPU time (user + system), wall time and peak memory (maximum resident set), and the CPU
microseconds per atom. Run from the repository root after building `surftrace` and
`surftrace_images`:

    /usr/bin/python3 bench/scale_bench.py make /tmp/scale            # the inputs (~400 MB)
    /usr/bin/python3 bench/scale_bench.py run /tmp/scale             # the table (minutes)
    /usr/bin/python3 bench/scale_bench.py read /tmp/scale --repeat 5 # reading speed, MB/s

Tiles are translated by the molecule's extent plus a gap (GAP_A, wider than two atoms and a
probe), so that no two tiles touch and every tile's surface is the same: an area is exactly
the tile count times 1AON's. The inputs are XYZR (the radii surftrace gives 1AON, written
exactly), PDB and GRO (read the same way as any file of those formats).
"""

import argparse
import csv
import io
import os
import re
import statistics
import subprocess
import sys
import tempfile

GAP_A = 10.0
SIZES = (1, 2, 3)  # tiles per axis: 1, 8, 27 copies
SOURCE = "tests/data/paper/1aon.pdb.gz"


def surftrace_path(args):
    return os.path.abspath(args.surftrace)


def read_atoms(surftrace):
    out = subprocess.run([surftrace, "info", SOURCE, "--atoms", "--format", "csv"], check=True,
                         capture_output=True, text=True).stdout
    return list(csv.DictReader(io.StringIO(out)))


def tiles(atoms, n):
    """Offsets of the n x n x n tiles: the extent of the molecule plus the gap per axis."""
    lo = [min(float(a[k]) for a in atoms) for k in "xyz"]
    hi = [max(float(a[k]) for a in atoms) for k in "xyz"]
    step = [hi[i] - lo[i] + GAP_A for i in range(3)]
    return [(ix * step[0], iy * step[1], iz * step[2])
            for ix in range(n) for iy in range(n) for iz in range(n)]


def write_xyzr(path, atoms, offsets):
    # The file's 3 decimals: the tile offsets move no digit beyond them.
    with open(path, "w") as f:
        for (dx, dy, dz) in offsets:
            for a in atoms:
                f.write("%.3f %.3f %.3f %s\n" % (float(a["x"]) + dx, float(a["y"]) + dy,
                                           float(a["z"]) + dz, a["radius"]))


def write_pdb(path, atoms, offsets):
    # Serial numbers wrap at 100000 as VMD and MDAnalysis write them; each tile repeats the
    # chains A-U, ended by TER.
    with open(path, "w") as f:
        serial = 0
        for (dx, dy, dz) in offsets:
            for a in atoms:
                serial += 1
                name = a["name"]
                name = name if len(name) == 4 or len(a["element"]) == 2 else " " + name
                f.write("%-6s%5d %-4s%1s%3s %1s%4d%1s   %8.3f%8.3f%8.3f%6.2f%6.2f          %2s\n" % (
                    "ATOM", serial % 100000, name, a["altloc"] or " ", a["resname"], a["chain"],
                    int(a["resid"]), a["icode"] or " ", float(a["x"]) + dx, float(a["y"]) + dy,
                    float(a["z"]) + dz, 1.0, 0.0, a["element"].upper()))
            f.write("TER\n")
        f.write("END\n")


def write_gro(path, atoms, offsets):
    # GRO: nm, fixed columns, numbers wrapping at 100000.
    count = len(atoms) * len(offsets)
    with open(path, "w") as f:
        f.write("1AON tiled %d times\n%5d\n" % (len(offsets), count))
        serial = 0
        for t, (dx, dy, dz) in enumerate(offsets):
            for a in atoms:
                serial += 1
                resid = (int(a["resid"]) + 1000 * t) % 100000
                f.write("%5d%-5s%5s%5d%8.3f%8.3f%8.3f\n" % (
                    resid, a["resname"], a["name"], serial % 100000,
                    (float(a["x"]) + dx) / 10, (float(a["y"]) + dy) / 10, (float(a["z"]) + dz) / 10))
        f.write("%10.5f%10.5f%10.5f\n" % (100.0, 100.0, 100.0))


def make(args):
    os.makedirs(args.dir, exist_ok=True)
    atoms = read_atoms(surftrace_path(args))
    for n in SIZES:
        offsets = tiles(atoms, n)
        stem = os.path.join(args.dir, "1aon_x%d" % n ** 3)
        write_xyzr(stem + ".xyzr", atoms, offsets)
        write_pdb(stem + ".pdb", atoms, offsets)
        write_gro(stem + ".gro", atoms, offsets)
        print("wrote %s.{xyzr,pdb,gro}: %d atoms" % (stem, len(atoms) * len(offsets)), file=sys.stderr)


def timed(cmd):
    """CPU seconds (user + system), wall seconds, peak resident MB of one whole process."""
    with tempfile.NamedTemporaryFile("r", suffix=".time") as t:
        run = subprocess.run(["/usr/bin/time", "-v", "-o", t.name] + cmd,
                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        if run.returncode != 0:
            raise SystemExit("failed: %s\n%s" % (" ".join(cmd), run.stderr[-2000:]))
        text = t.read()
    field = lambda label: float(re.search(re.escape(label) + r": ([0-9.]+)", text).group(1))
    user = field("User time (seconds)")
    system = field("System time (seconds)")
    wall = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): (\S+)", text).group(1)
    seconds = 0.0
    for part in wall.split(":"):
        seconds = seconds * 60 + float(part)
    rss = float(re.search(r"Maximum resident set size \(kbytes\): (\d+)", text).group(1))
    return user + system, seconds, rss / 1024


def run(args):
    st = surftrace_path(args)
    stp = tempfile.NamedTemporaryFile(suffix=".stp", delete=False).name
    png = tempfile.NamedTemporaryFile(suffix=".png", delete=False).name
    commands = [
        ("area", "ses", ["area", "{f}"]),
        ("area", "mss", ["area", "{f}", "--surface", "mss"]),
        ("build", "ses", ["build", "{f}", "-o", stp]),
        ("build", "mss", ["build", "{f}", "--surface", "mss", "-o", stp]),
        ("render", "ses", ["render", "{f}", "--size", "1024x1024", "-o", png]),
        ("render", "mss", ["render", "{f}", "--surface", "mss", "--size", "1024x1024", "-o", png]),
    ]
    only = set(args.only.split(",")) if args.only else None
    sizes = {int(n) for n in args.sizes.split(",")}
    surfaces = set(args.surfaces.split(","))
    print("| command | surface | atoms | CPU s | wall s (%d threads) | peak MB | CPU µs/atom |" % args.threads)
    print("|---|---|---|---|---|---|---|")
    for what, surface, argv in commands:
        if only and what not in only:
            continue
        for n in SIZES:
            if n ** 3 not in sizes or surface not in surfaces:
                continue
            f = os.path.join(args.dir, "1aon_x%d.xyzr" % n ** 3)
            atoms = sum(1 for _ in open(f))
            cmd = [st] + [a.format(f=f) for a in argv] + ["--threads", str(args.threads)]
            samples = [timed(cmd) for _ in range(args.repeat)]
            cpu = statistics.median(s[0] for s in samples)
            wall = statistics.median(s[1] for s in samples)
            rss = statistics.median(s[2] for s in samples)
            print("| %s | %s | %d | %.2f | %.2f | %.0f | %.1f |" % (
                what, surface, atoms, cpu, wall, rss, cpu / atoms * 1e6), flush=True)
    os.unlink(stp)
    os.unlink(png)


def read(args):
    st = surftrace_path(args)
    print("| format | atoms | MB | CPU s (median of %d) | MB/s | peak MB |" % args.repeat)
    print("|---|---|---|---|---|---|")
    for ext in ("xyzr", "pdb", "gro"):
        f = os.path.join(args.dir, "1aon_x27.%s" % ext)
        mb = os.path.getsize(f) / 1e6
        samples = [timed([st, "info", f]) for _ in range(args.repeat)]
        cpu = statistics.median(s[0] for s in samples)
        rss = statistics.median(s[2] for s in samples)
        print("| %s | %d | %.1f | %.2f | %.0f | %.0f |" % (ext, 1589490, mb, cpu, mb / cpu, rss), flush=True)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--surftrace", default="build/ci/tools/surftrace")
    sub = p.add_subparsers(dest="step", required=True)
    m = sub.add_parser("make", help="write the tiled inputs")
    m.add_argument("dir")
    r = sub.add_parser("run", help="area, build and render at each size")
    r.add_argument("dir")
    r.add_argument("--threads", type=int, default=2)
    r.add_argument("--repeat", type=int, default=1, help="runs per measure; the median is shown")
    r.add_argument("--only", help="comma-separated commands (area,build,render)")
    r.add_argument("--sizes", default="1,8,27", help="comma-separated tile counts (1,8,27)")
    r.add_argument("--surfaces", default="ses,mss", help="comma-separated surfaces (ses,mss)")
    rd = sub.add_parser("read", help="`info` on the 27x XYZR, PDB and GRO: reading speed")
    rd.add_argument("dir")
    rd.add_argument("--repeat", type=int, default=5)
    args = p.parse_args()
    {"make": make, "run": run, "read": read}[args.step](args)


if __name__ == "__main__":
    main()
