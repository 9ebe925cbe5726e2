#!/usr/bin/env python3
"""Start-up of the short commands: medians of wall and CPU time (user + system, from wait4)
of `info`, `area`, `build` and a 64x64 `render` of 1CRN (327 atoms), for one or more
`surftrace` programs, alternated run by run so that each sees the same load.

  python3 bench/startup_bench.py 9 before=/tmp/old/surftrace after=build/ci/tools/surftrace
"""
import os
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CRAMBIN = os.path.join(ROOT, "tests", "data", "structures", "1crn.pdb")


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    runs = int(sys.argv[1])
    programs = [arg.split("=", 1) for arg in sys.argv[2:]]
    out = tempfile.mkdtemp(prefix="surftrace_startup_")
    commands = {
        "info": ["info", CRAMBIN],
        "area": ["area", CRAMBIN],
        "build": ["build", CRAMBIN, "-o", os.path.join(out, "x.stp")],
        "render 64x64": ["render", CRAMBIN, "--size", "64x64", "-o", os.path.join(out, "x.png")],
    }
    for name, args in commands.items():
        times = {label: [] for label, _ in programs}
        for _ in range(runs):
            for label, program in programs:
                start = time.perf_counter()
                child = subprocess.Popen([program] + args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
                _, status, usage = os.wait4(child.pid, 0)
                if status != 0:
                    sys.exit(f"{program} {' '.join(args)}: exit status {status}")
                times[label].append((time.perf_counter() - start, usage.ru_utime + usage.ru_stime))
        for label, t in times.items():
            wall = statistics.median(x[0] for x in t)
            cpu = statistics.median(x[1] for x in t)
            print(f"{name:13s} {label:8s} wall {wall:.4f} s  cpu {cpu:.4f} s  (median of {len(t)})")


if __name__ == "__main__":
    main()
