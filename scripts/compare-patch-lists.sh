#!/usr/bin/env bash
# Builds the SES patch lists of 1VIS, 1AF6 and 1AON with two `surftrace` binaries and
# compares the .stp files byte for byte: a refactoring of the builder must not change them.
#   scripts/compare-patch-lists.sh OLD_SURFTRACE NEW_SURFTRACE [EXTRA BUILD ARGS...]
# e.g. build the base commit elsewhere (git archive BASE | tar -x -C /tmp/base, then
# cmake -S /tmp/base -B /tmp/base/build && cmake --build /tmp/base/build --target surftrace).
# Exits 1 when any list differs. SesBuilder's partial updates are checked equal to full
# builds bit for bit by tests/build/partial_update_test.cpp.
set -euo pipefail
if [ $# -lt 2 ]; then
  echo "usage: $0 OLD_SURFTRACE NEW_SURFTRACE [EXTRA BUILD ARGS...]" >&2
  exit 64
fi
old=$1 new=$2
shift 2
root=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
status=0
for pdb in 1vis 1af6 1aon; do
  in=$root/tests/data/paper/$pdb.pdb.gz
  "$old" build "$in" "$@" -o "$work/$pdb-old.stp" > /dev/null
  "$new" build "$in" "$@" -o "$work/$pdb-new.stp" > /dev/null
  if cmp -s "$work/$pdb-old.stp" "$work/$pdb-new.stp"; then
    echo "$pdb: identical ($(stat -c %s "$work/$pdb-new.stp") bytes)"
  else
    echo "$pdb: DIFFERENT"
    status=1
  fi
done
exit $status
