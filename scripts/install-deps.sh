#!/usr/bin/env bash
# Installs SurfTrace's build and test dependencies from Debian packages (bookworm).
# Idempotent: installs only what is missing; runs `apt-get update` at most once.
# Works as root or through sudo; prints what it does.
set -euo pipefail

packages=(
  build-essential cmake ninja-build ccache pkg-config
  libembree-dev libtbb-dev libglm-dev
  libopenimageio-dev openimageio-tools
  libgtest-dev libgmock-dev libbenchmark-dev
  gemmi-dev tao-pegtl-dev zlib1g-dev libgmp-dev libboost-dev
  libcgal-dev
  libegl-dev libgl-dev libopengl-dev libegl-mesa0 libgl1-mesa-dri glslang-tools
  nlohmann-json3-dev libcli11-dev
  freesasa
  python3-mdanalysis python3-numpy
  slurm-wlm munge
  clang libclang-rt-14-dev
)

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
