#!/usr/bin/env bash
# Quick start, part 2: install what is missing, then build and run every test twice:
# a Release build with warnings as errors, and an AddressSanitizer + UBSan build; then fuzz
# the file readers for about a minute (libFuzzer, ASan+UBSan; scripts/fuzz.sh); then run the
# README's first command, scripts/demo.sh, in a fresh minimal Debian 12 root (scripts/fresh-root.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh --tests
jobs=$(nproc)

# The fresh root depends on nothing built here (it clones HEAD and builds there), and most of
# its minutes are downloading and unpacking packages: it starts now, in the background, beside
# the builds; the last stage waits for it and prints its output. On an earlier failure the exit
# waits for it too rather than kill it (mmdebstrap unmounts what it mounted in the root).
mkdir -p build/fresh-root
bash scripts/fresh-root.sh >build/fresh-root/run.log 2>&1 &
fresh_root=$!
nonumpy=""
trap 'wait "$fresh_root" 2>/dev/null || true; rm -rf "$nonumpy"' EXIT

echo "== Release build (warnings are errors) =="
cmake --preset ci >/dev/null
cmake --build --preset ci -j "$jobs"
# All but python_module, which the next stage runs (the same pytest suite, with its count).
ctest --preset ci -j "$jobs" -E '^python_module$'

echo "== The Python module's tests (pytest, as ctest's python_module, here with their count) =="
PYTHONPATH=build/ci/python SURFTRACE_TOOL=build/ci/tools/surftrace SURFTRACE_BUILD_DIR=build/ci \
  /usr/bin/python3 -m pytest -q -p no:cacheprovider tests/python

echo "== The oracle tests with a numpy-less python3 first on PATH (a pyenv or venv) =="
# A python3 that cannot import numpy (no site-packages) shadows the system one: the oracle
# interpreter chosen at configure time must still be one that imports numpy and MDAnalysis,
# and the reader tests must pass under it. Not the *SharedData* ones (35 s, a third of the
# program's time where shared/data is present): they call the same oracle scripts through
# the same test::runOracleScript as the tests that run here, on larger files, and ctest ran them.
nonumpy=$(mktemp -d)
printf '#!/bin/sh\nexec /usr/bin/python3 -I -S "$@"\n' > "$nonumpy/python3"
chmod +x "$nonumpy/python3"
if PATH="$nonumpy:$PATH" python3 -c 'import numpy' 2>/dev/null; then
  echo "test.sh: the numpy-less python3 imports numpy" >&2; exit 1
fi
PATH="$nonumpy:$PATH" cmake -P cmake/OraclePython.cmake
PATH="$nonumpy:$PATH" ./build/ci/tests/reader_tests --gtest_brief=1 --gtest_filter='-*SharedData*'

echo "== AddressSanitizer + UBSan build =="
cmake --preset asan >/dev/null
cmake --build --preset asan -j "$jobs"
# Not the tests labelled release_only (the Release stage ran them): under ASan their minutes are
# llvmpipe's un-instrumented shaders or the same instrumented code again. tests/labels.cmake
# (release_only_tests) names, for each, the tests that run its code under ASan here.
ctest --preset asan -j "$jobs" -LE '^release_only$'

echo "== Fuzzing the readers (libFuzzer, ASan+UBSan, 10 s per format) =="
bash scripts/fuzz.sh 10

echo "== The README's first command in a fresh Debian 12 root (mmdebstrap; started after install-deps) =="
status=0
wait "$fresh_root" || status=$?
cat build/fresh-root/run.log
[ "$status" -eq 0 ] || exit "$status"
