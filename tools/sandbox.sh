#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Runs a command as root inside a throwaway copy-on-write view of this machine's own root
# filesystem, so that whatever it installs, removes or overwrites (apt-get install ./x.deb, dpkg's
# database, MeshLab's plugin folder, /usr/local) never reaches the machine:
#
#   tools/sandbox.sh [--bind DIR]... COMMAND [ARG...]
#
# - The view is an overlay (overlayfs): the machine's root filesystem as the read-only lower layer,
#   the changes in an upper layer on a private tmpfs that is thrown away when the command ends.
# - Bind-mounted read-write from the machine, so that outputs outlive the sandbox: the project tree
#   and every --bind DIR (e.g. a build folder outside the tree); /proc, /sys and /dev are mounted.
# - COMMAND runs in the current directory (which must exist in the view); its exit status is the
#   script's. Everything is unmounted when the script ends, also on failure or interruption.
# The tests use it where the README's install steps change the system (tests/e2e/package_test.sh).
# Needs root (mount, chroot). Costs well under a second: nothing is copied.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
die() { printf '[sandbox] error: %s\n' "$*" >&2; exit 1; }
[ "$(id -u)" -eq 0 ] || die "needs root (mount, chroot)"

binds=("$here")
while [ $# -gt 0 ] && [ "$1" = --bind ]; do
  [ $# -ge 2 ] || die "--bind needs a folder"
  binds+=("$(realpath "$2")"); shift 2
done
[ $# -ge 1 ] || { echo "usage: $0 [--bind DIR]... COMMAND [ARG...]" >&2; exit 2; }

top=$(mktemp -d /run/canonform-sandbox.XXXXXX 2>/dev/null || mktemp -d /tmp/canonform-sandbox.XXXXXX)
root=$top/root
mounted=()
cleanup() {
  local i
  for ((i = ${#mounted[@]} - 1; i >= 0; i--)); do
    umount "${mounted[i]}" 2>/dev/null || umount -l "${mounted[i]}" 2>/dev/null || true
  done
  rmdir "$top" 2>/dev/null || true
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# The upper layer on its own tmpfs: overlayfs refuses an upper layer inside its lower layer.
mount -t tmpfs -o mode=0700 canonform-sandbox "$top"
mounted+=("$top")
mkdir -p "$top/upper" "$top/work" "$root"
mount -t overlay canonform-sandbox -o "lowerdir=/,upperdir=$top/upper,workdir=$top/work" "$root" ||
  die "could not mount an overlay of / (overlayfs missing from the kernel?)"
mounted+=("$root")
mount -t proc proc "$root/proc"; mounted+=("$root/proc")
mount --rbind /sys "$root/sys"; mount --make-rslave "$root/sys"; mounted+=("$root/sys")
mount --rbind /dev "$root/dev"; mount --make-rslave "$root/dev"; mounted+=("$root/dev")
for d in "${binds[@]}"; do
  [ -d "$d" ] || die "no folder $d to bind"
  mkdir -p "$root$d"
  mount --bind "$d" "$root$d"; mounted+=("$root$d")
done

cwd=$(pwd)
set +e
chroot "$root" /usr/bin/env CANONFORM_IN_SANDBOX=1 bash -c 'cd "$1" && shift && exec "$@"' sandbox "$cwd" "$@"
rc=$?
set -e
exit $rc
