#!/usr/bin/env bash
# Installs SurfTrace's dependencies from Debian packages (bookworm).
#
#   bash scripts/install-deps.sh           what building and running surftrace need (scripts/demo.sh)
#   bash scripts/install-deps.sh --tests   that, and every test tool and oracle (scripts/test.sh)
#   bash scripts/install-deps.sh --list [--tests]   print the package names and install nothing
#
# Idempotent: installs only what is missing; runs `apt-get update` at most once.
# Works as root or through sudo; prints what it does.
set -euo pipefail

# Building the library and the `surftrace` program, and running it (GL through Mesa's EGL).
run_packages=(
  build-essential cmake ninja-build ccache pkg-config
  libembree-dev libtbb-dev libglm-dev libopenimageio-dev
  gemmi-dev tao-pegtl-dev zlib1g-dev libgmp-dev libboost-dev
  libegl-dev libgl-dev libopengl-dev libegl-mesa0 libgl1-mesa-dri
  nlohmann-json3-dev libcli11-dev
)
# The test suites, benchmarks and their oracles: GoogleTest and Google Benchmark, the shader
# checker, CGAL (test oracle only), FreeSASA, MDAnalysis, a one-node Slurm, clang's libFuzzer,
# and headless Chromium (opens `compare --html`'s page).
test_packages=(
  libgtest-dev libgmock-dev libbenchmark-dev
  glslang-tools openimageio-tools
  libcgal-dev
  freesasa
  chromium
  python3-mdanalysis python3-numpy
  slurm-wlm munge
  clang libclang-rt-14-dev
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

echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
