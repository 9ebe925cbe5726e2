#!/usr/bin/env bash
# Quick start, part 1: install what is missing, build (Release), and run SurfTrace on the
# bundled demo molecule (1VIS, mevalonate kinase, 2531 atoms).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release --target surftrace
demo=tests/data/paper/1vis.pdb.gz
./build/release/tools/surftrace info "$demo"
echo
./build/release/tools/surftrace area "$demo" --probe 1.4
./build/release/tools/surftrace build "$demo" --probe 1.4 -o build/release/1vis.stp
