#!/usr/bin/env bash
# Quick start, part 2: install what is missing, then build and run every test twice:
# a Release build with warnings as errors, and an AddressSanitizer + UBSan build; then fuzz
# the file readers for about a minute (libFuzzer, ASan+UBSan; scripts/fuzz.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
jobs=$(nproc)

echo "== Release build (warnings are errors) =="
cmake --preset ci >/dev/null
cmake --build --preset ci -j "$jobs"
ctest --preset ci -j "$jobs"

echo "== AddressSanitizer + UBSan build =="
cmake --preset asan >/dev/null
cmake --build --preset asan -j "$jobs"
ctest --preset asan -j "$jobs"

echo "== Fuzzing the readers (libFuzzer, ASan+UBSan, 10 s per format) =="
bash scripts/fuzz.sh 10
