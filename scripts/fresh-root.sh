#!/usr/bin/env bash
# The README's first command on a fresh Debian 12 machine, for real: makes a minimal Debian 12
# root with mmdebstrap (--variant=minbase: only the essential packages and apt, none of the
# project's), puts a clone of this repository in it, runs `bash scripts/demo.sh` there as a user
# would (as root, no standard input), and checks that out/1vis.png and out/1vis.exr exist and
# are 1024x1024 images. Exit 0 when they are; otherwise 1, with the demo's log.
#
#   bash scripts/fresh-root.sh [REPOSITORY]   a clone of REPOSITORY's HEAD (default: this one's;
#                                            commit what you want tested)
#
# The root is mmdebstrap's own (its "null" format): it makes it in a temporary folder, mounts
# /dev, /proc and /sys for the commands run inside and unmounts them itself, and deletes the
# root when done; this script never deletes a root. The downloaded packages are kept between
# runs in $SURFTRACE_FRESH_ROOT_CACHE (default /var/cache/surftrace-fresh-root), which is safe:
# apt checks every package against the signed index before it uses one. The package sources are
# the host's Debian ones (/etc/apt/sources.list.d/debian.sources or /etc/apt/sources.list).
# Needs root (mmdebstrap's root mode mounts and chroots) and the network to Debian's mirrors.
set -euo pipefail
repo=${1:-$(cd "$(dirname "$0")/.." && pwd)}
cache=${SURFTRACE_FRESH_ROOT_CACHE:-/var/cache/surftrace-fresh-root}
say() { echo "fresh-root: $*"; }
die() { echo "fresh-root: $*" >&2; exit 1; }

[ "$(id -u)" -eq 0 ] || die "needs root (mmdebstrap mounts /proc and /dev inside the root it makes); run it as root"
command -v mmdebstrap >/dev/null || die "mmdebstrap is not installed: bash scripts/install-deps.sh --tests installs it"
command -v iinfo >/dev/null || die "iinfo (openimageio-tools) is not installed: bash scripts/install-deps.sh --tests"

# The host's Debian package sources, and nothing else (no third-party repositories).
sources=""
if [ -f /etc/apt/sources.list.d/debian.sources ]; then
  sources=/etc/apt/sources.list.d/debian.sources
elif [ -s /etc/apt/sources.list ] && grep -q '^deb .*debian' /etc/apt/sources.list; then
  sources=/etc/apt/sources.list
else
  die "found no Debian package sources on this machine (/etc/apt/sources.list.d/debian.sources or /etc/apt/sources.list)"
fi

log=$repo/build/fresh-root/demo.log
work=$(mktemp -d /tmp/surftrace-fresh-root.XXXXXX)
trap 'rm -rf --one-file-system "$work"' EXIT   # the clone and what came out of the root; never a root
git -C "$repo" rev-parse --verify -q HEAD >/dev/null || die "$repo is not a git repository with a commit"
git clone -q --no-hardlinks "$repo" "$work/surftrace"
commit=$(git -C "$work/surftrace" rev-parse --short HEAD)
if [ -n "$(git -C "$repo" status --porcelain --untracked-files=no)" ]; then
  say "note: $repo has uncommitted changes; the root gets a clone of HEAD ($commit) without them"
fi
mkdir -p "$cache" "$work/out"
# Keep the cache from growing without bound across Debian's point releases.
if [ "$(du -sm "$cache" | cut -f1)" -gt 3000 ]; then say "the package cache passed 3 GB; emptying it"; rm -rf --one-file-system "${cache:?}"/*; fi

say "making a minimal Debian 12 root (mmdebstrap --variant=minbase, sources from $sources) and running"
say "bash scripts/demo.sh in a clone of $commit there (its output: $log)"
start=$(date +%s)
# The demo's exit status is written out rather than failing the hook, so that the packages it
# downloaded reach the cache and its outputs are copied out either way.
status=0
mmdebstrap --quiet --variant=minbase --mode=root --format=null --skip=essential/unlink \
  --setup-hook="mkdir -p \"\$1\"/var/cache/apt/archives/" \
  --setup-hook="sync-in $cache /var/cache/apt/archives/" \
  --customize-hook="copy-in $work/surftrace /root" \
  --customize-hook='chroot "$1" env -i HOME=/root PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin LANG=C.UTF-8 CI=true bash -c "cd /root/surftrace && { bash scripts/demo.sh > /root/demo.log 2>&1; echo \$? > /root/demo.status; mkdir -p out; }" </dev/null' \
  --customize-hook="sync-out /var/cache/apt/archives $cache" \
  --customize-hook="copy-out /root/demo.status /root/demo.log $work" \
  --customize-hook="sync-out /root/surftrace/out $work/out" \
  bookworm /dev/null "$sources" || status=$?
minutes=$(( ($(date +%s) - start + 30) / 60 ))
if [ "$status" -ne 0 ]; then
  die "mmdebstrap could not make or run the root (exit $status, after $minutes min); see its messages above (no network to Debian's mirrors? no root?)"
fi
mkdir -p "$(dirname "$log")"
cp "$work/demo.log" "$log" 2>/dev/null || true
demo=$(cat "$work/demo.status" 2>/dev/null || echo missing)
if [ "$demo" != 0 ]; then
  echo "fresh-root: the last 40 lines of the demo's output ($log):" >&2
  tail -n 40 "$log" >&2 || true
  die "bash scripts/demo.sh failed in a fresh Debian 12 root (exit $demo, after $minutes min); its whole output: $log"
fi
for image in 1vis.png 1vis.exr; do
  [ -s "$work/out/$image" ] || die "the demo exited 0 but wrote no out/$image"
  info=$(iinfo "$work/out/$image") || die "out/$image is not an image iinfo can read"
  grep -q ": 1024 x 1024," <<<"$info" || die "out/$image is not the 1024x1024 image the README promises: $info"
done
say "bash scripts/demo.sh passed in a fresh Debian 12 root in $minutes min: out/1vis.png and out/1vis.exr are 1024x1024 images"
