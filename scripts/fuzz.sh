#!/usr/bin/env bash
# Fuzzes the readers of untrusted files (PDB, mmCIF, PQR, XYZR, XYZ, .stp) with libFuzzer
# under ASan+UBSan, seeded with tests/data. Usage: scripts/fuzz.sh [SECONDS_PER_TARGET] [TARGET...]
# (default 10 s each, all nine targets: pdb mmcif pqr xyzr xyz stp dcd xtc gro). Corpora grow in
# build/fuzz/corpus/<target> across runs; a crash is saved in build/fuzz/crashes/<target>/
# and fails the run: reduce it, fix it, and add it to tests/data/bad (see tests/fuzz/README.md).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-10}
shift || true
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(pdb mmcif pqr xyzr xyz stp dcd xtc gro)

if ! command -v clang++ >/dev/null 2>&1; then
  echo "fuzz: clang++ not found (Debian: clang, libclang-rt-14-dev); skipped" >&2
  exit 0
fi
CC=clang CXX=clang++ cmake -S tests/fuzz -B build/fuzz -G Ninja >/dev/null
if ! cmake --build build/fuzz -j "${FUZZ_JOBS:-$(nproc)}" >build/fuzz/build.log 2>&1; then
  { grep -E "error|undefined reference" build/fuzz/build.log || true; } | head -20 >&2
  echo "fuzz: the fuzzers did not build (whole log: build/fuzz/build.log). tests/fuzz/sources.cmake" \
    "lists the sources the readers need by hand: add any new one they call." >&2
  exit 1
fi

# Seeds: the files of tests/data (and tests/fuzz/seeds) in each format, up to 64 KiB each,
# gzipped ones included (the readers gunzip by content).
seeds_for() {
  case "$1" in
    pdb) find tests/data tests/fuzz/seeds -type f \( -name '*.pdb' -o -name '*.pdb.gz' -o -name '*.ent' \) ;;
    mmcif) find tests/data tests/fuzz/seeds -type f \( -name '*.cif' -o -name '*.cif.gz' \) ;;
    pqr) find tests/data tests/fuzz/seeds -type f -name '*.pqr' ;;
    xyzr) find tests/data tests/fuzz/seeds -type f -name '*.xyzr' ;;
    xyz) find tests/data tests/fuzz/seeds -type f -name '*.xyz' ;;
    stp) find tests/fuzz/seeds/stp tests/data/stp -type f -name '*.stp' ;;
    dcd) find tests/data -type f -name '*.dcd' -size -64k ;;
    xtc) find tests/data -type f -name '*.xtc' -size -64k ;;
    gro) find tests/data -type f -name '*.gro' -size -64k ;;
  esac
}

# One target: seeds its corpus, fuzzes it for $seconds, and writes its summary line to
# build/fuzz/<target>.summary (its result first: ok or FAILED).
fuzz_one() {
  local t=$1 corpus crashes log result runs cov files
  corpus=build/fuzz/corpus/$t
  crashes=build/fuzz/crashes/$t
  mkdir -p "$corpus" "$crashes"
  while IFS= read -r f; do
    [ "$(stat -c %s "$f")" -le 65536 ] || continue
    name=$(echo "$f" | tr '/' '_')
    if [ "$t" = stp ]; then
      # The harness reads a mode byte first: odd passes the file as it is, even wraps a body
      # (the file without its 24-byte header and 4-byte checksum) in a valid header and CRC.
      { printf '\001'; cat "$f"; } >"$corpus/raw_$name"
      { printf '\000'; tail -c +25 "$f" | head -c -4; } >"$corpus/body_$name"
    else
      cp "$f" "$corpus/$name"
    fi
  done < <(seeds_for "$t")
  log=build/fuzz/$t.log
  if ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
     build/fuzz/fuzz_$t "$corpus" -max_total_time="$seconds" -max_len=65536 -timeout=20 -rss_limit_mb=2560 \
       -print_final_stats=1 -artifact_prefix="$crashes/" >"$log" 2>&1; then
    result=ok
  else
    result="FAILED (see $log and $crashes/)"
  fi
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo '?')
  cov=$(grep -oE 'cov: [0-9]+ ft: [0-9]+' "$log" | tail -1 || echo 'cov: ?')
  files=$(find "$corpus" -type f | wc -l)
  printf '%-6s %-5s %9s runs in %ss, %s, corpus %s files\n' "$t" "$result" "$runs" "$seconds" "$cov" "$files" \
    >"build/fuzz/$t.summary"
}

# The targets run side by side, FUZZ_PARALLEL (default: one per core) at a time: each libFuzzer
# process is single-threaded and -max_total_time is its own wall time, so each target still
# gets its seconds on a core of its own, and the stage takes a fraction of their sum.
parallel=${FUZZ_PARALLEL:-$(nproc)}
running=0
for t in "${targets[@]}"; do
  rm -f "build/fuzz/$t.summary"
  fuzz_one "$t" &
  running=$((running + 1))
  if [ "$running" -ge "$parallel" ]; then
    wait -n || true  # a target that failed to finish leaves no summary: FAILED below
    running=$((running - 1))
  fi
done
wait
status=0
for t in "${targets[@]}"; do
  line=$(cat "build/fuzz/$t.summary" 2>/dev/null || printf '%-6s FAILED (no summary: see build/fuzz/%s.log)' "$t" "$t")
  printf 'fuzz: %s\n' "$line"
  [[ "$line" == *" ok "* ]] || status=1
done
exit $status
