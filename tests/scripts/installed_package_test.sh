#!/usr/bin/env bash
# The installed library as a program meets it: `cmake --install` of this build into a fresh
# prefix, examples/cpp configured and built there against find_package(SurfTrace) alone (no
# path into the source or build tree), then run on 1CRN. Its SES area must be the one
# `surftrace area --format json` prints, to the last digit, and its PNG a 256x256 image with
# something drawn in it, the pixels of `surftrace render` with the same choices.
#   installed_package_test.sh SOURCE_DIR BUILD_DIR SURFTRACE CXX_COMPILER BUILD_TYPE CXX_FLAGS EXE_LINKER_FLAGS
set -euo pipefail
source_dir=$1 build_dir=$2 surftrace=$3 compiler=$4 build_type=$5 cxx_flags=${6-} linker_flags=${7-}
structure=$source_dir/tests/data/structures/1crn.pdb

work=$(mktemp -d "${TMPDIR:-/tmp}/surftrace-installed.XXXXXX")
trap 'rm -rf "$work"' EXIT
fail() { echo "installed_package_test: $*" >&2; exit 1; }

cmake --install "$build_dir" --prefix "$work/prefix" >"$work/install.log" ||
  { cat "$work/install.log"; fail "cmake --install $build_dir failed"; }
[ -f "$work/prefix/lib/cmake/SurfTrace/SurfTraceConfig.cmake" ] ||
  fail "cmake --install wrote no lib/cmake/SurfTrace/SurfTraceConfig.cmake: find_package(SurfTrace) cannot work"
# A package that names the source or build tree works here and nowhere else.
if leaks=$(grep -rlF -e "$source_dir" -e "$(cd "$build_dir" && pwd)" "$work/prefix/lib/cmake" "$work/prefix/include"); then
  fail "installed files name the source or build tree (the installed package must stand alone): $leaks"
fi

# The example, configured as a user would, in a folder outside the source tree.
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S "$source_dir/examples/cpp" -B "$work/example" -G Ninja -DCMAKE_PREFIX_PATH="$work/prefix" \
      -DCMAKE_CXX_COMPILER="$compiler" -DCMAKE_BUILD_TYPE="$build_type" -DCMAKE_CXX_FLAGS="$cxx_flags" \
      -DCMAKE_EXE_LINKER_FLAGS="$linker_flags" "${launcher[@]}" >"$work/configure.log" 2>&1 ||
  { cat "$work/configure.log"; fail "configuring examples/cpp against the installed package failed"; }
cmake --build "$work/example" -v >"$work/build.log" 2>&1 ||
  { cat "$work/build.log"; fail "building examples/cpp against the installed package failed"; }
if grep -F -e "-I$source_dir" -e "-isystem $source_dir" "$work/build.log"; then
  fail "examples/cpp was compiled with an include path into the source tree"
fi

"$work/example/surface_example" "$structure" "$work/1crn.png" >"$work/example.out" ||
  { cat "$work/example.out"; fail "examples/cpp's program failed on $structure"; }
cat "$work/example.out"
"$surftrace" area "$structure" --format json >"$work/area.json"
# Both print the shortest digits that read back as the double: equal text is equal doubles.
python3 - "$work/example.out" "$work/area.json" <<'PY'
import json, re, sys
printed = re.search(r"^SES area (\S+) ", open(sys.argv[1]).read(), re.M)
if not printed:
    sys.exit("installed_package_test: the example printed no 'SES area VALUE' line")
expected = json.load(open(sys.argv[2]))["ses"]["total"]
if printed.group(1) != repr(expected) or float(printed.group(1)) != expected:
    sys.exit(f"installed_package_test: the example's SES area {printed.group(1)} is not "
             f"`surftrace area`'s {expected!r}")
print(f"SES area {printed.group(1)}: the same as `surftrace area --format json`")
PY

info=$(iinfo --stats "$work/1crn.png") || fail "the example's PNG is not an image iinfo can read"
grep -q ": *256 x *256," <<<"$info" || fail "the example's PNG is not 256x256: $info"
grep -q "Constant: No" <<<"$info" || fail "the example's PNG is one colour (nothing drawn): $info"
# The library through the installed package draws what the program draws from the same choices.
"$surftrace" render "$structure" -o "$work/cli.png" --size 256x256 --color element >/dev/null
hashes=$(iinfo --hash "$work/1crn.png" "$work/cli.png" | grep -o 'SHA-1: .*' | sort -u | wc -l)
[ "$hashes" -eq 1 ] || fail "the example's pixels differ from \`surftrace render --size 256x256 --color element\`'s"
echo "the example's PNG is a 256x256 image of the surface, pixel for pixel \`surftrace render\`'s"
