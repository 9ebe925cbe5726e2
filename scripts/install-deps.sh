#!/usr/bin/env bash
# Installs SurfTrace's dependencies from Debian packages (bookworm).
#
#   bash scripts/install-deps.sh           what building and running surftrace need (scripts/demo.sh)
#   bash scripts/install-deps.sh --tests   that, and every test tool and oracle (scripts/test.sh)
#   bash scripts/install-deps.sh --list [--tests]   print the package names and install nothing
#
# Idempotent: installs only what is missing; runs `apt-get update` at most once.
# Works as root or through sudo; prints what it does. When another apt-get or dpkg holds the
# package lock (a fresh cloud machine running its unattended upgrades), it waits for it, saying
# so, for up to SURFTRACE_APT_LOCK_WAIT seconds (default 900), then fails naming the holder.
set -euo pipefail

# Building the library and the `surftrace` program, and running it (GL through Mesa's EGL).
run_packages=(
  build-essential cmake ninja-build ccache pkg-config
  libembree-dev libtbb-dev libglm-dev libopenimageio-dev
  # Debian's OpenImageIOTargets.cmake names the programs of openimageio-tools (iconvert, ...)
  # and stops the configure when they are missing, though nothing here runs them.
  openimageio-tools
  gemmi-dev tao-pegtl-dev zlib1g-dev libgmp-dev libboost-dev
  libegl-dev libgl-dev libopengl-dev libegl-mesa0 libgl1-mesa-dri
  nlohmann-json3-dev libcli11-dev
  # Meshes in and out (`compare MESH ...`, `mesh`): OBJ, PLY, STL, OFF, glTF/GLB.
  libassimp-dev
)
# The test suites, benchmarks and their oracles: GoogleTest and Google Benchmark, the shader
# checker, CGAL (test oracle only), FreeSASA, MDAnalysis, a one-node Slurm, clang's libFuzzer,
# headless Chromium (opens `compare --html`'s page), and the Python module's build (pybind11),
# tests (pytest) and examples (pandas, matplotlib).
test_packages=(
  libgtest-dev libgmock-dev libbenchmark-dev
  glslang-tools
  libcgal-dev
  freesasa
  chromium
  python3-mdanalysis python3-numpy
  pybind11-dev python3-pybind11 python3-pytest python3-pandas python3-matplotlib
  slurm-wlm munge
  clang libclang-rt-14-dev
  mmdebstrap
)

list=0
tests=0
for arg in "$@"; do
  case "$arg" in
    --tests) tests=1 ;;
    --list) list=1 ;;
    *) echo "install-deps: unknown option '$arg' (expected --tests or --list)" >&2; exit 2 ;;
  esac
done

packages=("${run_packages[@]}")
if [ "$tests" -eq 1 ]; then packages+=("${test_packages[@]}"); fi

if [ "$list" -eq 1 ]; then
  printf '%s\n' "${packages[@]}"
  exit 0
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
    echo "install-deps: missing packages: ${missing[*]}" >&2
    echo "install-deps: not root and no sudo; install them and re-run" >&2
    exit 1
  fi
fi

# Runs apt-get with the given arguments; while it fails because another process holds one of
# apt's or dpkg's locks, waits and tries again, up to $lock_wait seconds in all.
lock_wait=${SURFTRACE_APT_LOCK_WAIT:-900}
lock_poll=${SURFTRACE_APT_LOCK_POLL:-10}
waited=0
apt_get() {
  local log status
  log=$(mktemp)
  while true; do
    status=0
    $SUDO apt-get "$@" 2>"$log" || status=$?
    cat "$log" >&2
    if [ "$status" -eq 0 ]; then rm -f "$log"; return 0; fi
    if ! grep -q "Could not get lock\|Unable to acquire the dpkg frontend lock\|is another process using it" "$log"; then
      rm -f "$log"; return "$status"
    fi
    local holder
    holder=$(grep -o "held by process [0-9]* ([^)]*)" "$log" | head -1 || true)
    if [ "$waited" -ge "$lock_wait" ]; then
      echo "install-deps: apt's lock is still ${holder:-held by another process} after ${waited} s;" \
           "wait for it to finish (or stop it) and run this again" >&2
      rm -f "$log"; return "$status"
    fi
    echo "install-deps: another apt-get or dpkg holds the package lock${holder:+ (${holder#held by })};" \
         "waiting for it (${waited} s of at most ${lock_wait} s)" >&2
    sleep "$lock_poll"
    waited=$((waited + lock_poll))
  done
}

echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
apt_get update -qq
apt_get install -y -qq --no-install-recommends "${missing[@]}"
