#!/usr/bin/env bash
# slurm_array_test.sh SURFTRACE_BINARY TOPOLOGY TRAJECTORY [extra render options...]
#
# End-to-end test of frame sharding under a real Slurm job array:
#   1. starts a private one-node Slurm cluster on localhost (slurm_cluster.sh) in a
#      temporary directory; it is stopped again on exit, whatever happens;
#   2. submits surftrace_array.sbatch with `sbatch --array=0-3 --wait`; every task
#      runs `srun SURFTRACE trajectory TOPOLOGY TRAJECTORY -o frames/%05d.png
#      [extra options]` in WORK/slurm (OUTDIR_slurm = WORK/slurm/frames) and picks
#      its shard from SLURM_ARRAY_TASK_ID/COUNT itself;
#   3. runs the very same command line once locally, unsharded, in WORK/single
#      (OUTDIR_single = WORK/single/frames);
#   4. checks: all 4 tasks ran (as job steps) and succeeded, the two sets of frame
#      files are equal, every frame was written exactly once and by the task that
#      owns it (the i-th selected frame, i counted from 0 in the single run's
#      frames, goes to task i mod 4), and every file is byte-identical (cmp) to
#      the single run's.
# The output pattern is relative and the inputs absolute, so that both runs have the
# same command line: surftrace records its command line in the PNG metadata
# (tEXt "surftrace:command"), so a different -o path alone makes the bytes differ.
# To count writes without relying on the command's stdout, the job runs SURFTRACE
# through a small recorder: it runs the real binary with the same arguments and the
# same SLURM_* environment, but from a fresh, empty private working directory, lists
# what appeared there in a per-task ledger and then moves it into OUTDIR_slurm.
#
# Exit status: 0 pass (one summary line on stdout), 1 fail (with the reason and the
# logs), 2 usage, 77 skip: only when the Slurm/munge programs are not installed.
# The whole test ends within 8 minutes even if something hangs.
# Needs root (the test cluster runs its daemons and jobs as root).
# Environment: SURFTRACE_SLURM_KEEP=1 keeps the temporary directory;
#              SURFTRACE_SLURM_TEST_LIMIT=S lowers the time limit (60..420 s);
#              SURFTRACE_SLURM_TMP=DIR creates it under DIR (default /tmp; keep the
#              path short: the munge socket path must fit in 108 bytes).
set -uo pipefail

HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd -P)
SELF=$HERE/$(basename "${BASH_SOURCE[0]}")
NTASKS=4
TOTAL_LIMIT=420      # s, for everything but the final cleanup
# a smaller limit may be asked for (e.g. to test the time-out path), never a larger one
[[ ${SURFTRACE_SLURM_TEST_LIMIT:-} =~ ^[0-9]+$ ]] && ((SURFTRACE_SLURM_TEST_LIMIT >= 60 &&
    SURFTRACE_SLURM_TEST_LIMIT < TOTAL_LIMIT)) && TOTAL_LIMIT=$SURFTRACE_SLURM_TEST_LIMIT
KILL_GRACE=45        # s, for the cleanup after TERM; 420 + 45 < 480

say() { echo "slurm_array_test: $*" >&2; }

usage() {
    echo "usage: $0 SURFTRACE_BINARY TOPOLOGY TRAJECTORY [extra render options...]" >&2
    exit 2
}

# ---------------------------------------------------------------------------
# outer process: argument checks, the skip decision, and the global time limit
if [[ -z ${_SURFTRACE_SLURM_TEST_INNER:-} ]]; then
    (($# >= 3)) || usage
    missing=()
    for t in sbatch srun sinfo squeue scontrol scancel slurmctld slurmd munged; do
        command -v "$t" >/dev/null 2>&1 || missing+=("$t")
    done
    if ((${#missing[@]})); then
        echo "SKIP: Slurm/munge not installed (missing: ${missing[*]});" \
             "install them with: apt-get install -y --no-install-recommends slurm-wlm munge"
        exit 77
    fi
    export _SURFTRACE_SLURM_TEST_INNER=1
    timeout -k "$KILL_GRACE" "$TOTAL_LIMIT" bash "$SELF" "$@"
    rc=$?
    if ((rc == 124 || rc == 137)); then
        echo "FAIL: slurm array test did not finish within ${TOTAL_LIMIT} s (killed)"
        exit 1
    fi
    exit "$rc"
fi

# ---------------------------------------------------------------------------
# inner process
# fds 3/4: the test's own stdout/stderr, also valid inside redirected commands
# (a signal trap may run while a redirection is in effect)
exec 3>&1 4>&2
say() { echo "slurm_array_test: $*" >&4; }
T_START=$SECONDS
DEADLINE=$((TOTAL_LIMIT - 30))   # leave time for the checks and the error report
left() { local l=$((DEADLINE - SECONDS)); ((l > 1)) && echo "$l" || echo 1; }

fail() {
    echo "FAIL: $*" >&3
    exit 1
}

for t in timeout setsid flock ss cmp comm; do
    command -v "$t" >/dev/null 2>&1 || fail "required tool '$t' not found"
done
[[ $(id -u) == 0 ]] || fail "must run as root (the test cluster runs slurmd and its jobs as root)"

abspath() { local d; d=$(cd "$(dirname "$1")" 2>/dev/null && pwd -P) || return 1; echo "${d%/}/$(basename "$1")"; }

BIN=$1 TOPOLOGY=$2 TRAJECTORY=$3
shift 3
EXTRA=("$@")
if [[ $BIN == */* ]]; then
    BIN=$(abspath "$BIN") || fail "no such surftrace binary: $1"
else
    BIN=$(command -v "$BIN") || fail "surftrace binary '$1' not found in PATH"
fi
[[ -f $BIN && -x $BIN ]] || fail "not an executable file: $BIN"
[[ -r $TOPOLOGY ]] || fail "cannot read topology: $TOPOLOGY"
[[ -r $TRAJECTORY ]] || fail "cannot read trajectory: $TRAJECTORY"
TOPOLOGY=$(abspath "$TOPOLOGY"); TRAJECTORY=$(abspath "$TRAJECTORY")
for a in "${EXTRA[@]}"; do
    [[ $a =~ [[:space:]] ]] && fail "extra option '$a' contains blanks (SURFTRACE_ARGS is split at blanks)"
done

# nothing from an enclosing Slurm job may leak into this test
unset $(compgen -e | grep '^SLURM_') 2>/dev/null

WORK=$(mktemp -d "${SURFTRACE_SLURM_TMP:-/tmp}/surftrace-slurm.XXXXXX") || fail "mktemp failed"
chmod 0711 "$WORK"   # munged wants every directory above its socket searchable by all
CLUSTER=$WORK/cluster
PATTERN=frames/%05d.png                  # relative to the working directory
OUT_SLURM=$WORK/slurm/frames             # OUTDIR_slurm
OUT_SINGLE=$WORK/single/frames           # OUTDIR_single
REC=$WORK/recorder
mkdir -p "$WORK/slurm" "$WORK/single" "$REC" "$WORK/logs" "$WORK/bin"

# long commands run in the background so that a signal is handled at once
CHILD=""
run_child() {
    "$@" &
    CHILD=$!
    wait "$CHILD"
    local rc=$?
    CHILD=""
    return "$rc"
}

cleanup() {
    local rc=$?
    trap - EXIT INT TERM HUP
    [[ -n $CHILD ]] && kill -TERM "$CHILD" 2>/dev/null
    bash "$HERE/slurm_cluster.sh" stop "$CLUSTER" >&4 2>&4
    if [[ ${SURFTRACE_SLURM_KEEP:-0} == 1 ]]; then
        say "kept $WORK"
    else
        rm -rf "$WORK"
    fi
    exit "$rc"
}
trap cleanup EXIT
trap 'say "interrupted"; exit 1' INT TERM HUP

show_job_logs() {
    local f
    for f in "$WORK"/logs/*.out; do
        [[ -e $f ]] || continue
        echo "----- $f"; tail -n 20 "$f"
    done
    for f in "$REC"/*.ledger; do
        [[ -e $f ]] || continue
        echo "----- $f (first lines)"; head -n 5 "$f"
    done
    bash "$HERE/slurm_cluster.sh" logs "$CLUSTER" 2>&1
}

# --- 1. cluster --------------------------------------------------------------
t0=$SECONDS
SLURM_CLUSTER_OWNER_PID=$$ timeout 90 bash "$HERE/slurm_cluster.sh" start "$CLUSTER" \
    || fail "could not start the Slurm test cluster (see the log tails above)"
export SLURM_CONF=$CLUSTER/etc/slurm.conf
T_CLUSTER=$((SECONDS - t0))

# --- 2. the array job ----------------------------------------------------------
cat >"$WORK/bin/surftrace-recorder" <<'EOF'
#!/usr/bin/env bash
# Runs the real surftrace with the same arguments and environment, but in a fresh,
# empty working directory (the output pattern is relative); then records every file
# that appeared there in this task's ledger and moves it to OUTDIR in the job's
# working directory.
set -u
start=$PWD
priv=$(mktemp -d "$REC_DIR/private.XXXXXX") || exit 1
cd "$priv" || exit 1
"$REAL_SURFTRACE" "$@"
rc=$?
task=${SLURM_ARRAY_TASK_ID:-none}
{
    echo "# task=$task count=${SLURM_ARRAY_TASK_COUNT:-} min=${SLURM_ARRAY_TASK_MIN:-}" \
         "job=${SLURM_JOB_ID:-} step=${SLURM_STEP_ID:-} rc=$rc"
    # paths relative to OUTDIR; anything written elsewhere is marked
    find . -type f | sed 's|^\./||' | LC_ALL=C sort |
        sed "s|^$OUTDIR/||; t; s|^|OUTSIDE-OUTDIR:|"
} >"$REC_DIR/task_$task.$$.ledger"
find . -type f | sed 's|^\./||' | while IFS= read -r f; do
    mkdir -p "$start/$(dirname "$f")" && mv -f "$priv/$f" "$start/$f"
done
exit "$rc"
EOF
chmod +x "$WORK/bin/surftrace-recorder"

# inputs of surftrace_array.sbatch, exported to the job (sbatch --export=ALL)
export TOPOLOGY TRAJECTORY OUTDIR=${PATTERN%/*}
export SURFTRACE=$WORK/bin/surftrace-recorder REAL_SURFTRACE=$BIN REC_DIR=$REC
export SURFTRACE_ARGS="${EXTRA[*]}"

t0=$SECONDS
say "cluster up in ${T_CLUSTER} s; submitting sbatch --array=0-$((NTASKS - 1)) --wait"
JOBID=""
run_child timeout "$(left)" sbatch --wait --parsable --export=ALL \
    --array=0-$((NTASKS - 1)) --cpus-per-task=1 --job-name=surftrace-test \
    --chdir="$WORK/slurm" --output="$WORK/logs/surftrace_%A_%a.out" \
    "$HERE/surftrace_array.sbatch" >"$WORK/sbatch.out" 2>"$WORK/sbatch.err"
rc=$?
JOBID=$(head -n1 "$WORK/sbatch.out" | cut -d';' -f1)
T_ARRAY=$((SECONDS - t0))
if ((rc != 0)); then
    cat "$WORK/sbatch.err"
    timeout 10 scontrol show job "$JOBID" 2>/dev/null | grep -E 'JobId=|JobState=|ExitCode='
    show_job_logs
    ((rc == 124)) && fail "array job $JOBID did not finish in time"
    fail "array job ${JOBID:-?} failed (sbatch --wait exit status $rc)"
fi
[[ $JOBID =~ ^[0-9]+$ ]] || fail "could not read the job id from sbatch (got '$JOBID')"

# --- 3. the same command in one local process, unsharded -----------------------
t0=$SECONDS
say "array job $JOBID done in ${T_ARRAY} s; running the single local process"
run_child env -C "$WORK/single" -u SLURM_CONF timeout "$(left)" "$BIN" trajectory \
    "$TOPOLOGY" "$TRAJECTORY" -o "$PATTERN" "${EXTRA[@]}" >"$WORK/logs/single.out" 2>&1
rc=$?
T_SINGLE=$((SECONDS - t0))
if ((rc != 0)); then
    tail -n 20 "$WORK/logs/single.out"
    ((rc == 124)) && fail "the single local run did not finish in time"
    fail "the single local run failed (exit status $rc)"
fi
say "single run done in ${T_SINGLE} s; comparing"

# --- 4. checks ---------------------------------------------------------------------
list_files() { (cd "$1" && find . -type f | sed 's|^\./||' | LC_ALL=C sort); }

declare -A position=()
# The selected frames in order are the single run's frame numbers, sorted: the i-th of them
# (from 0) belongs to task i mod NTASKS (for the default --frames, i is the frame number k).
i=0
while IFS= read -r n; do
    position[$((10#$n))]=$i
    i=$((i + 1))
done < <(cd "$OUT_SINGLE" && find . -type f -printf '%f\n' | sed 's/\..*//' | grep -E '^[0-9]+$' | sort -n -u)

# 4a. every task ran exactly once, as a job step of this job, and succeeded
declare -A owner=() seen=()
problems=()
# note PROBLEM: record it, but only the first 5 of a kind verbatim
declare -A kind_count=()
note() {
    local kind=$1; shift
    kind_count[$kind]=$(( ${kind_count[$kind]:-0} + 1 ))
    ((kind_count[$kind] <= 5)) && problems+=("$*")
    ((kind_count[$kind] == 6)) && problems+=("... (more of: $kind)")
    return 0
}
for ((t = 0; t < NTASKS; t++)); do
    ledgers=("$REC/task_$t".*.ledger)
    [[ -e ${ledgers[0]} ]] || { problems+=("task $t never ran surftrace"); continue; }
    ((${#ledgers[@]} == 1)) || problems+=("task $t ran surftrace ${#ledgers[@]} times")
    for l in "${ledgers[@]}"; do
        head -n1 "$l" | grep -q " count=$NTASKS min=0 job=[0-9][0-9]* step=[0-9][0-9]* rc=0$" ||
            problems+=("task $t: unexpected ledger header: $(head -n1 "$l")")
        while IFS= read -r f; do
            [[ $f == \#* || -z $f ]] && continue
            if [[ $f == OUTSIDE-OUTDIR:* ]]; then
                problems+=("task $t wrote ${f#OUTSIDE-OUTDIR:} outside the output directory")
                continue
            fi
            seen[$f]=$(( ${seen[$f]:-0} + 1 ))
            owner[$f]+="$t "
            # 4b. the frame number in the name is k, the i-th selected frame; task t owns
            # i mod NTASKS == t
            b=$(basename "$f"); n=${b%%.*}
            if [[ $n =~ ^[0-9]+$ ]]; then
                p=${position[$((10#$n))]:-}
                if [[ -z $p ]]; then
                    note "frames in the wrong shard" "frame $f written by task $t, but the single run has no such frame"
                elif (( p % NTASKS != t )); then
                    note "frames in the wrong shard" \
                        "frame $f (selected frame $p) written by task $t, but it belongs to task $(( p % NTASKS ))"
                fi
            fi
        done <"$l"
    done
done
others=$(find "$REC" -name '*.ledger' ! -name 'task_[0-9]*' | head -n3)
[[ -z $others ]] || problems+=("surftrace ran outside the array tasks: $others")

# 4c. exactly once
for f in "${!seen[@]}"; do
    ((seen[$f] == 1)) || note "frames written more than once" \
        "frame $f written ${seen[$f]} times (tasks ${owner[$f]% })"
done

# 4d. same set of files as the single run
list_files "$OUT_SLURM" >"$WORK/list_slurm"
list_files "$OUT_SINGLE" >"$WORK/list_single"
NFRAMES=$(wc -l <"$WORK/list_single")
((NFRAMES > 0)) || problems+=("the single run wrote no files (see $WORK/logs/single.out)")
only_slurm=$(LC_ALL=C comm -23 "$WORK/list_slurm" "$WORK/list_single" | head -n5 | tr '\n' ' ')
only_single=$(LC_ALL=C comm -13 "$WORK/list_slurm" "$WORK/list_single" | head -n5 | tr '\n' ' ')
[[ -z $only_slurm ]] || problems+=("only in the slurm output: $only_slurm")
[[ -z $only_single ]] || problems+=("missing from the slurm output: $only_single")
unrecorded=$(LC_ALL=C comm -23 "$WORK/list_slurm" <(printf '%s\n' "${!seen[@]}" | LC_ALL=C sort) | head -n5 | tr '\n' ' ')
[[ -z $unrecorded ]] || problems+=("files in the slurm output that no task recorded: $unrecorded")

# 4e. byte-identical
while IFS= read -r f; do
    if [[ -f $OUT_SLURM/$f ]] && ! cmp -s "$OUT_SLURM/$f" "$OUT_SINGLE/$f"; then
        note "frames that differ" "frame $f differs from the single run"
    fi
done <"$WORK/list_single"

if ((${#problems[@]})); then
    for k in "${!kind_count[@]}"; do problems+=("$k: ${kind_count[$k]}"); done
    printf '  %s\n' "${problems[@]}"
    show_job_logs
    fail "slurm array output does not match the single run (see the problems above)"
fi

say "timings: cluster start ${T_CLUSTER} s, array job ${T_ARRAY} s, single run ${T_SINGLE} s, total $((SECONDS - T_START)) s"
echo "slurm array: $NTASKS tasks, $NFRAMES frames, all equal to the single run"
exit 0
