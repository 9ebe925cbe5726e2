#!/usr/bin/env bash
# Every file that the CMake package files of the demo's packages name (the IMPORTED_LOCATION of
# each imported target, which CMake checks at configure time) belongs to a package that the
# demo's set installs, directly or through its dependencies. Debian's libopenimageio-dev names
# the programs of openimageio-tools, and a configure without them stops; on a machine that has
# the test set this hides, so the check reads the packages' own metadata (dpkg, apt-cache).
set -euo pipefail
script="$1"
mapfile -t demo < <(bash "$script" --list)
closure=$(apt-cache depends --recurse --no-recommends --no-suggests --no-conflicts --no-breaks \
            --no-replaces --no-enhances "${demo[@]}" 2>/dev/null | grep -v '^ ' | sed 's/:.*//' | sort -u)
fail=0
checked=0
for p in "${demo[@]}"; do
  dpkg-query -W "$p" >/dev/null 2>&1 || { echo "$p is not installed here: run install-deps.sh"; fail=1; continue; }
  while read -r targets; do
    # Files named through ${_IMPORT_PREFIX}: the package's prefix, /usr for Debian's.
    while read -r file; do
      file=${file//\$\{_IMPORT_PREFIX\}/\/usr}
      checked=$((checked + 1))
      owner=$(dpkg-query -S "$file" 2>/dev/null | head -1 | sed 's/:.*//; s/, .*//') || true
      if [ -z "$owner" ]; then
        echo "$targets names $file, which no installed package holds"; fail=1
      elif ! grep -qx "$owner" <<<"$closure"; then
        echo "$targets names $file of $owner, which the demo's set does not install (add $owner to it)"; fail=1
      fi
    done < <(grep -o '"\${_IMPORT_PREFIX}/[^"]*"' "$targets" | tr -d '"' | grep -v '/include' | sort -u)
  done < <(dpkg-query -L "$p" | grep -E '/cmake/.*Targets-[a-z]*\.cmake$' || true)
done
[ "$fail" -eq 0 ] && echo "the demo's set holds all $checked files its CMake packages import"
exit "$fail"
