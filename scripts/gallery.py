#!/usr/bin/env python3
"""Renders the README's lighting gallery: 1VIS and 1AON, SES and skin, under each --lighting
preset, at 1024x1024 with the Embree engine, timing each render (the whole `surftrace render`
process, wall clock), and writes the images (JPEG) and a Markdown table of them with their
times and commands.

    python3 scripts/gallery.py [--surftrace build/ci/tools/surftrace] [--size 1024]
                               [--out docs/images/gallery] [--table docs/images/gallery/README.md]
                               [--threads N] [--only SUBSTRING]

Needs the `surftrace` program (build it first, e.g. `bash scripts/demo.sh` or
`cmake --preset ci && cmake --build --preset ci`) and `oiiotool` (Debian: openimageio-tools,
installed with the demo's packages) to write the JPEGs. Standard library only.
"""
import argparse
import os
import platform
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

MOLECULES = [
    # (name, file, colouring): 1VIS by element, 1AON (21 chains) by chain.
    ("1vis", "tests/data/paper/1vis.pdb.gz", ["--color", "element"]),
    ("1aon", "tests/data/paper/1aon.pdb.gz", ["--color", "chain"]),
]
SURFACES = [
    ("ses", ["--surface", "ses"]),
    ("skin", ["--surface", "mss", "--shrink", "0.5"]),
]
PRESETS = ["headlight", "simple", "soft", "full"]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--surftrace", default=str(ROOT / "build/ci/tools/surftrace"),
                        help="the surftrace program (default: build/ci/tools/surftrace)")
    parser.add_argument("--size", type=int, default=1024, help="image side in pixels (default 1024)")
    parser.add_argument("--out", default=str(ROOT / "docs/images/gallery"), help="folder for the JPEGs")
    parser.add_argument("--table", default=None,
                        help="Markdown table to write (default: OUT/README.md)")
    parser.add_argument("--threads", type=int, default=None, help="surftrace --threads (default: all cores)")
    parser.add_argument("--only", default="", help="render only images whose name contains this")
    parser.add_argument("--quality", type=int, default=88, help="JPEG quality (default 88)")
    args = parser.parse_args()

    surftrace = Path(args.surftrace)
    if not surftrace.is_file() or not os.access(surftrace, os.X_OK):
        sys.exit(f"gallery: {surftrace} is not an executable surftrace program; build it first "
                 "(bash scripts/demo.sh, or cmake --preset ci && cmake --build --preset ci), or give --surftrace")
    oiiotool = shutil.which("oiiotool")
    if oiiotool is None:
        sys.exit("gallery: oiiotool not found (Debian: apt-get install openimageio-tools)")
    if args.size < 16 or args.size > 8192:
        sys.exit(f"gallery: --size {args.size} is outside [16, 8192]")
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    table = Path(args.table) if args.table else out / "README.md"

    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for mol, path, colour in MOLECULES:
            for surface, surface_args in SURFACES:
                for preset in PRESETS:
                    name = f"{mol}-{surface}-{preset}"
                    if args.only and args.only not in name:
                        continue
                    png = Path(tmp) / f"{name}.png"
                    cmd = [str(surftrace), "render", str(ROOT / path), *surface_args, *colour,
                           "--lighting", preset, "--size", f"{args.size}x{args.size}", "--quiet", "-o", str(png)]
                    if args.threads:
                        cmd += ["--threads", str(args.threads)]
                    print(f"gallery: {name} ...", end="", flush=True)
                    before = resource.getrusage(resource.RUSAGE_CHILDREN)
                    start = time.perf_counter()
                    run = subprocess.run(cmd, capture_output=True, text=True)
                    seconds = time.perf_counter() - start
                    after = resource.getrusage(resource.RUSAGE_CHILDREN)
                    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
                    if run.returncode != 0:
                        print()
                        sys.exit(f"gallery: `{' '.join(cmd)}` failed ({run.returncode}):\n{run.stderr}")
                    jpg = out / f"{name}.jpg"
                    subprocess.run([oiiotool, str(png), "--compression", f"jpeg:{args.quality}", "-o", str(jpg)],
                                   check=True)
                    print(f" {seconds:.1f} s wall, {cpu:.1f} s CPU")
                    shown = " ".join(["surftrace", "render", path, *surface_args, *colour, "--lighting", preset,
                                      "--size", f"{args.size}x{args.size}", "-o", f"{name}.png"])
                    rows.append((mol, surface, preset, jpg.name, seconds, cpu, shown))

    threads = args.threads or os.cpu_count()
    lines = [
        f"# Lighting gallery",
        "",
        f"Made by `python3 scripts/gallery.py` at {args.size}×{args.size} with the Embree engine, "
        f"{threads} threads, on {platform.machine()} with {os.cpu_count()} cores (load average "
        f"{os.getloadavg()[0]:.1f} at the end). Each time is the whole `surftrace render` process "
        "(reading, building the surface, tracing, writing), one run: its wall-clock time, and its CPU time "
        "(user + system, all threads), which other work on the machine disturbs less.",
        "",
        "| molecule | surface | lighting | image | wall | CPU | command |",
        "| --- | --- | --- | --- | --- | --- | --- |",
    ]
    for mol, surface, preset, image, seconds, cpu, shown in rows:
        lines.append(f'| {mol.upper()} | {surface} | `{preset}` | <a href="{image}"><img src="{image}" width="200" alt="{mol} {surface} {preset}"></a> '
                     f"| {seconds:.1f} s | {cpu:.1f} s | `{shown}` |")
    table.write_text("\n".join(lines) + "\n")
    print(f"gallery: {len(rows)} images in {out}, table {table}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
