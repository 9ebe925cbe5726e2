#!/bin/bash
# The speed and scale targets (docs/benchmarks.md, "The speed targets in one sitting"): two builds
# side by side, process by process, interleaved, so that both see the same load.
#
#   bash bench/targets.sh OLD_DIR NEW_DIR [SCALE_DIR] > log
#
# OLD_DIR and NEW_DIR each hold a `surftrace` and a `surftrace_frame_bench` (copies of
# build/ci/tools/surftrace and build/ci/bench/surftrace_frame_bench of the two commits);
# SCALE_DIR holds the tiled inputs of `bench/scale_bench.py make` (default /tmp/scale).
# Lines: `measure OLD|NEW` then the frame bench's JSON, or `elapsed user sys peak-KiB` of
# /usr/bin/time for whole processes. Run from the repository root; takes ~15 min on 2 cores.
set -euo pipefail
OLD=$(realpath "$1") NEW=$(realpath "$2") SCALE=${3:-/tmp/scale}
P=tests/data/paper/1aon.pdb.gz
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$NEW/surftrace" build "$P" -o "$work/ses.stp" >&2
"$NEW/surftrace" build "$P" --surface mss --shrink 0.5 -o "$work/mss.stp" >&2
t() { /usr/bin/time -f "%e %U %S %M" "$@" 2>&1 >/dev/null | tail -1; }
frame() { "$1/surftrace_frame_bench" "$P" "$2" --threads 2 "${@:3}" 2>&1 | tail -1; }
echo "start $(date -u +%T) $(uptime)"
for r in 1 2 3 4 5; do
  for b in OLD NEW; do
    d=${!b}
    echo "frame_opaque $b $(frame "$d" "$work/ses.stp" --frames 3)"
    echo "frame_transp $b $(frame "$d" "$work/ses.stp" --frames 1 --opacity 0.4 --max-layers 4)"
    echo "frame_skin_opaque $b $(frame "$d" "$work/mss.stp" --frames 3)"
    echo "frame_skin_transp $b $(frame "$d" "$work/mss.stp" --frames 1 --opacity 0.4 --max-layers 4)"
    echo "area_mss $b $(t "$d/surftrace" area "$P" --surface mss --shrink 0.5)"
    echo "build_mss $b $(t "$d/surftrace" build "$P" --surface mss --shrink 0.5 -o "$work/out.stp")"
    echo "build_ses $b $(t "$d/surftrace" build "$P" -o "$work/out.stp")"
    for f in xyzr pdb gro; do echo "info_$f $b $(t "$d/surftrace" info "$SCALE/1aon_x27.$f")"; done
  done
  echo "round $r $(date -u +%T) $(uptime)"
done
for r in 1 2 3; do
  for b in OLD NEW; do
    d=${!b}
    for n in 1 8 27; do echo "area_x$n $b $(t "$d/surftrace" area "$SCALE/1aon_x$n.xyzr")"; done
  done
  echo "round_tiles $r $(date -u +%T) $(uptime)"
done
echo "end $(date -u +%T)"
