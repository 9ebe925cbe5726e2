#!/usr/bin/env bash
# Re-renders the reference images from their recipes: reference/<case>/recipe.args holds the
# `surftrace render` arguments (paths relative to the repository root); image.exr (every
# buffer) and image.png (for people) are written beside it. Changing a reference is a
# deliberate act: run this, look at the PNGs and `git diff --stat reference/`, and say why
# in the commit message. Usage: scripts/update-reference.sh [CASE...] (default: all).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake --preset release >/dev/null
cmake --build --preset release --target surftrace >/dev/null
cases=("$@")
if [ ${#cases[@]} -eq 0 ]; then
  for d in reference/*/; do cases+=("$(basename "$d")"); done
fi
for c in "${cases[@]}"; do
  recipe="reference/$c/recipe.args"
  [ -f "$recipe" ] || { echo "update-reference: no $recipe" >&2; exit 1; }
  # shellcheck disable=SC2046
  ./build/release/tools/surftrace render $(cat "$recipe") --quiet \
    --exr "reference/$c/image.exr" -o "reference/$c/image.png"
done
