#!/usr/bin/env python3
"""Renders the README's lighting gallery: 1VIS and 1AON, SES and skin, under each --lighting
preset, at 1024x1024 with the Embree engine, timing each render (the whole `surftrace render`
process: wall clock and CPU), and writes the images (JPEG), their times (OUT/times.json), a
page with every image, time and command (OUT/README.md), and the grid in README.md between
<!-- gallery:begin --> and <!-- gallery:end -->.

    python3 scripts/gallery.py [--surftrace build/ci/tools/surftrace] [--size 1024]
                               [--out docs/images/gallery] [--threads N] [--only SUBSTRING]
    python3 scripts/gallery.py --tables-only     # the page and the grid again, from times.json

Needs the `surftrace` program (build it first, e.g. `bash scripts/demo.sh` or
`cmake --preset ci && cmake --build --preset ci`) and `oiiotool` (Debian: openimageio-tools,
installed with the demo's packages) to write the JPEGs. Standard library only.
"""
import argparse
import json
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
    parser.add_argument("--readme", default=str(ROOT / "README.md"),
                        help="README whose grid (between <!-- gallery:begin --> and <!-- gallery:end -->) to rewrite")
    parser.add_argument("--tables-only", action="store_true",
                        help="render nothing: rewrite the page and the README's grid from OUT/times.json")
    args = parser.parse_args()

    out = Path(args.out)
    table = Path(args.table) if args.table else out / "README.md"
    if args.tables_only:
        write_tables(out, table, Path(args.readme))
        return 0
    surftrace = Path(args.surftrace)
    if not surftrace.is_file() or not os.access(surftrace, os.X_OK):
        sys.exit(f"gallery: {surftrace} is not an executable surftrace program; build it first "
                 "(bash scripts/demo.sh, or cmake --preset ci && cmake --build --preset ci), or give --surftrace")
    oiiotool = shutil.which("oiiotool")
    if oiiotool is None:
        sys.exit("gallery: oiiotool not found (Debian: apt-get install openimageio-tools)")
    if args.size < 16 or args.size > 8192:
        sys.exit(f"gallery: --size {args.size} is outside [16, 8192]")
    out.mkdir(parents=True, exist_ok=True)

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

    if rows:
        threads = args.threads or os.cpu_count()
        record = {"size": args.size, "threads": threads, "machine": platform.machine(), "cores": os.cpu_count(),
                  "load": round(os.getloadavg()[0], 1), "images": {}}
        times_file = out / "times.json"
        if args.only and times_file.exists():
            record["images"] = json.loads(times_file.read_text())["images"]
        for mol, surface, preset, image, seconds, cpu, shown in rows:
            record["images"][image] = {"wall": round(seconds, 2), "cpu": round(cpu, 2), "command": shown}
        times_file.write_text(json.dumps(record, indent=1) + "\n")
    write_tables(out, table, Path(args.readme))
    return 0


def write_tables(out: Path, table: Path, readme: Path) -> None:
    """The gallery page (OUT/README.md: a grid, then every image's times and command) and the
    grid in the README between its gallery markers, both from OUT/times.json."""
    times_file = out / "times.json"
    if not times_file.exists():
        sys.exit(f"gallery: {times_file} is missing; render the gallery first")
    record = json.loads(times_file.read_text())
    images = record["images"]

    def grid(prefix: str, width: int) -> list:
        lines = ["| | " + " | ".join(f"`{p}`" for p in PRESETS) + " |", "|---" * (len(PRESETS) + 1) + "|"]
        for mol, _, _ in MOLECULES:
            for surface, _ in SURFACES:
                cells = []
                for preset in PRESETS:
                    image = f"{mol}-{surface}-{preset}.jpg"
                    if image not in images:
                        cells.append("")
                        continue
                    cells.append(f'<a href="{prefix}{image}"><img src="{prefix}{image}" width="{width}" '
                                 f'alt="{mol.upper()} {surface} {preset}"></a><br>{images[image]["cpu"]:.1f} s CPU')
                lines.append(f"| {mol.upper()} {surface} | " + " | ".join(cells) + " |")
        return lines

    about = (f"{record['size']}×{record['size']}, Embree, {record['threads']} threads on {record['cores']} "
             f"{record['machine']} cores (load average {record['load']}). A time is the CPU time (user + system, "
             "all threads) of the whole `surftrace render` process: reading, building the surface, tracing, "
             "writing; it is what other work on the machine disturbs least.")
    page = ["# Lighting gallery", "", f"Made by `python3 scripts/gallery.py`: {about}", "", *grid("", 180), "",
            "| image | wall | CPU | command |", "| --- | --- | --- | --- |"]
    for image, t in images.items():
        page.append(f"| [{image}]({image}) | {t['wall']:.1f} s | {t['cpu']:.1f} s | `{t['command']}` |")
    table.write_text("\n".join(page) + "\n")

    begin, end = "<!-- gallery:begin -->", "<!-- gallery:end -->"
    text = readme.read_text()
    if begin in text and end in text:
        rel = os.path.relpath(out, readme.parent).replace(os.sep, "/") + "/"
        block = [begin, "", *grid(rel, 150), "", f"{about} Every image's command: [{rel}README.md]({rel}README.md).",
                 "", end]
        head, rest = text.split(begin, 1)
        text = head + "\n".join(block) + rest.split(end, 1)[1]
        readme.write_text(text)
        print(f"gallery: the grid in {readme} is rewritten")
    print(f"gallery: {len(images)} images in {out}, page {table}")


if __name__ == "__main__":
    sys.exit(main())
