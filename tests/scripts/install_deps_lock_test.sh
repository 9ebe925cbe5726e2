#!/usr/bin/env bash
# scripts/install-deps.sh while another apt-get holds the package lock (a fresh cloud machine
# running its unattended upgrades): it waits, saying so, and goes on once the lock is free; it
# gives up after SURFTRACE_APT_LOCK_WAIT seconds naming the holder; any other apt failure stops
# it at once. apt-get and dpkg-query are stand-ins on PATH that play the lock's holder, so the
# machine's packages are never touched.
set -euo pipefail
script="$1"
fake=$(mktemp -d)
trap 'rm -rf "$fake"' EXIT
# Every package is "missing", so the script goes on to apt-get.
printf '#!/bin/sh\nexit 1\n' > "$fake/dpkg-query"
# apt-get fails with apt's own lock messages while $fake/held holds a count above 0.
cat > "$fake/apt-get" <<'STUB'
#!/bin/sh
echo "$*" >> "$FAKE/calls"
mode=$(cat "$FAKE/mode")
if [ "$mode" = broken ]; then echo "E: Unable to locate package frobnicate" >&2; exit 100; fi
left=$(cat "$FAKE/held")
if [ "$left" -gt 0 ]; then
  echo $((left - 1)) > "$FAKE/held"
  echo "E: Could not get lock /var/lib/dpkg/lock-frontend. It is held by process 4242 (unattended-upgr)" >&2
  echo "E: Unable to acquire the dpkg frontend lock (/var/lib/dpkg/lock-frontend), is another process using it?" >&2
  exit 100
fi
exit 0
STUB
printf '#!/bin/sh\necho 0\n' > "$fake/id"
chmod +x "$fake"/*
export FAKE="$fake" PATH="$fake:$PATH" SURFTRACE_APT_LOCK_POLL=1
fail=0

# 1. The lock is held for two tries, then released: exit 0, two waiting lines, update retried.
echo ok > "$fake/mode"; echo 2 > "$fake/held"; : > "$fake/calls"
if ! out=$(SURFTRACE_APT_LOCK_WAIT=60 bash "$script" 2>&1); then echo "a released lock failed the install:"; echo "$out"; fail=1; fi
waits=$(grep -c "holds the package lock (process 4242 (unattended-upgr)); waiting" <<<"$out" || true)
[ "$waits" -eq 2 ] || { echo "expected 2 waiting lines, saw $waits:"; echo "$out"; fail=1; }
updates=$(grep -c "^update" "$fake/calls" || true); installs=$(grep -c "^install" "$fake/calls" || true)
[ "$updates" -eq 3 ] && [ "$installs" -eq 1 ] || { echo "apt-get calls: $(cat "$fake/calls")"; fail=1; }

# 2. The lock is never released: fails after the wait, naming the holder and what to do.
echo 1000 > "$fake/held"
if out=$(SURFTRACE_APT_LOCK_WAIT=3 bash "$script" 2>&1); then echo "a lock never released passed"; fail=1; fi
grep -q "still held by process 4242 (unattended-upgr) after 3 s" <<<"$out" || { echo "no give-up line:"; echo "$out"; fail=1; }

# 3. Any other failure stops at once, without waiting.
echo broken > "$fake/mode"; : > "$fake/calls"
if out=$(SURFTRACE_APT_LOCK_WAIT=60 bash "$script" 2>&1); then echo "a broken apt-get passed"; fail=1; fi
if grep -q waiting <<<"$out"; then echo "waited on a failure that is not the lock:"; echo "$out"; fail=1; fi
[ "$(wc -l < "$fake/calls")" -eq 1 ] || { echo "retried a failure that is not the lock"; fail=1; }

[ "$fail" -eq 0 ] && echo "install-deps waits for the package lock, gives up naming its holder, and stops on other failures"
exit "$fail"
