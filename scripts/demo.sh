#!/usr/bin/env bash
# Quick start, part 1: install what is missing, build (Release), and ray-trace the SES of the
# bundled demo molecule (1VIS, mevalonate kinase, 2531 atoms) to out/1vis.png, with every
# per-pixel buffer (depth, normal, patch kind and id, atom id, flags) in out/1vis.exr.
set -euo pipefail
cd "$(dirname "$0")/.."
# Only what building and running need: the test tools (Slurm, clang, CGAL, MDAnalysis, ...)
# come with scripts/test.sh. So the tests and benchmarks are not configured here.
bash scripts/install-deps.sh
cmake --preset release -DSURFTRACE_BUILD_TESTS=OFF -DSURFTRACE_BUILD_BENCHMARKS=OFF -DSURFTRACE_BUILD_PYTHON=OFF >/dev/null
cmake --build --preset release --target surftrace
demo=tests/data/paper/1vis.pdb.gz
mkdir -p out
./build/release/tools/surftrace info "$demo"
echo
./build/release/tools/surftrace area "$demo" --probe 1.4
echo
./build/release/tools/surftrace render "$demo" --probe 1.4 --size 1024x1024 --spp 4 \
  -o out/1vis.png --exr out/1vis.exr
echo "Open out/1vis.png (convex patches green, toroidal yellow, concave red)."
