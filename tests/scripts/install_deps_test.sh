#!/usr/bin/env bash
# scripts/install-deps.sh: the demo's set (building and running) holds none of the test tools,
# and the test set holds the demo's and every tool the tests run.
set -euo pipefail
script="$1"
run=$(bash "$script" --list)
all=$(bash "$script" --list --tests)
fail=0
for tool in slurm-wlm munge clang libclang-rt-14-dev libcgal-dev freesasa python3-mdanalysis \
            libgtest-dev libbenchmark-dev chromium \
            pybind11-dev python3-pybind11 python3-pytest python3-pandas; do
  if grep -qx "$tool" <<<"$run"; then echo "the demo installs the test tool $tool"; fail=1; fi
  if ! grep -qx "$tool" <<<"$all"; then echo "--tests misses $tool"; fail=1; fi
done
for needed in cmake libembree-dev libtbb-dev libopenimageio-dev gemmi-dev libgmp-dev libcli11-dev libegl-mesa0; do
  if ! grep -qx "$needed" <<<"$run"; then echo "the demo misses $needed"; fail=1; fi
done
while read -r p; do
  if ! grep -qx "$p" <<<"$all"; then echo "--tests drops the demo's $p"; fail=1; fi
done <<<"$run"
if bash "$script" --frobnicate >/dev/null 2>&1; then echo "an unknown option is accepted"; fail=1; fi
[ "$fail" -eq 0 ] && echo "install-deps sets: demo $(wc -l <<<"$run") packages, tests $(wc -l <<<"$all")"
exit "$fail"
