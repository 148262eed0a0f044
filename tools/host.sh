#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Runs a command inside a Debian root filesystem of another release:
#
#   tools/host.sh SUITE COMMAND [ARG...]
#   tools/host.sh trixie canonform-meshlab in.off out.ply --filter generate_euclidean_canonical_form
#   tools/host.sh forky meshlab --version
#
#   SUITE        Debian     what it is
#   trixie       trixie     a MeshLab 2022.02 user's system, with our plugins built and installed there
#   forky        forky      a MeshLab 2025.07 user's system, the same
#   forky-bare   forky      a MeshLab 2025.07 user's system as apt leaves it after `apt install meshlab`:
#                           none of the libraries our plugins link (the portable archives are tried
#                           there: tests/e2e/portable_test.sh)
#   bullseye     bullseye   the system the portable archives are built in (glibc 2.31, GCC 10,
#                           Qt 5.15.2: tools/package.sh --portable); no MeshLab
#   bookworm-new bookworm   a new user's Debian 12 as its installer leaves it (mmdebstrap's variant
#                           important: debootstrap's, the installer's base system), nothing else: the
#                           README's commands from bare metal (tools/readme_commands.sh)
#   RELEASE-python          bullseye, bookworm, trixie, forky: a Python user's system, Debian's
#                           python3, venv, numpy, matplotlib and pytest, no compiler (the wheel is
#                           tried there: tests/e2e/wheel_venv_test.sh)
#
#   tools/host.sh --make SUITE      makes SUITE's root filesystem (step 1) if it is not cached, and
#                                   nothing else
#   tools/host.sh --prepare SUITE   steps 1 to 3, no command: tools/run_tests.sh prepares every
#                                   suite the tests use at once, alongside the build
#
# 1. The root filesystem is made once with Debian's mmdebstrap (variant apt, unless said above) from
#    the machine's own Debian mirror (derived from its apt entry): for trixie and forky the packages
#    that `tools/setup.sh plugins` installs (meshlab, compiler, Qt5, Xvfb, ...: what step 3 needs),
#    for the others the lists below. It is cached outside the clone in $CANONFORM_HOST_CACHE (default
#    /var/cache/canonform/hosts) as SUITE-KEY, KEY a hash of the suite and the package list; it is
#    never changed after it is made.
# 2. Each clone runs it through an overlay (its changes under build/hosts/SUITE/upper), with the
#    project tree (at its own path) and /tmp bind-mounted, proc and dev mounted; bullseye also gets
#    a compiler cache, $CANONFORM_HOST_CACHE/ccache-bullseye, as /var/cache/ccache (CCACHE_DIR;
#    CANONFORM_HOST_CCACHE=0: none). The mounts are made in a mount namespace of the script's own,
#    so no other process sees them and they go when it ends, however it ends (also on SIGKILL); it
#    also unmounts them itself on failure or interruption.
# 3. trixie and forky only: inside, the README's commands for that system: tools/build.sh
#    --plugins (its set-up, then what the package holds; build dir build/hosts/SUITE/build),
#    tools/package.sh, then `apt-get install ./canonform-plugins-*.deb`
#    (only when the package changed). CANONFORM_HOST_PREPARE=0 skips this step.
# 4. COMMAND runs inside as root, in the current directory if it is under the project tree or
#    /tmp (else the project root); its exit status is the script's.
# A second run costs seconds: the root filesystem is cached, the build is up to date.
# Needs root (mmdebstrap, mount, chroot).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)

usage() { echo "usage: $0 trixie|forky|forky-bare|bullseye|bookworm-new|{bullseye,bookworm,trixie,forky}-python COMMAND [ARG...] | --make SUITE | --prepare SUITE" >&2; exit 2; }
only=""  # --make: step 1 alone; --prepare: steps 1 to 3, no command
case "${1:-}" in
  --make|--prepare) only=$1; shift; [ $# -eq 1 ] || usage ;;
  *) [ $# -ge 2 ] || usage ;;
esac
suite=$1; shift
variant=apt
case "$suite" in
  trixie|forky) release=$suite; prepare=1 ;;  # our plugins built and installed inside (step 3)
  forky-bare) release=forky; prepare=0 ;;
  bullseye) release=bullseye; prepare=0 ;;
  bookworm-new) release=bookworm; prepare=0; variant=important ;;
  bullseye-python|bookworm-python|trixie-python|forky-python) release=${suite%-python}; prepare=0 ;;
  *) usage ;;
esac
log() { printf '[host %s] %s\n' "$suite" "$*" >&2; }
die() { printf '[host %s] error: %s\n' "$suite" "$*" >&2; exit 1; }
[ "$(id -u)" -eq 0 ] || die "needs root (mmdebstrap, mount, chroot)"
# Everything below runs in a mount namespace of its own (util-linux unshare, private propagation):
# the overlay and its bind mounts (/tmp, /dev, the project tree) exist only there and vanish with
# its last process, also when the script is killed with SIGKILL (a ctest timeout, a session that
# ends). Left in the parent namespace they made `rm -rf build` reach through them into /tmp, /dev
# and the clone itself.
if [ -z "${CANONFORM_HOST_IN_NAMESPACE:-}" ]; then
  command -v unshare > /dev/null || die "unshare missing (util-linux)"
  if [ -n "$only" ]; then set -- "$only" "$suite"; else set -- "$suite" "$@"; fi
  exec env CANONFORM_HOST_IN_NAMESPACE=1 unshare --mount --propagation private -- bash "$0" "$@"
fi

cache=${CANONFORM_HOST_CACHE:-/var/cache/canonform/hosts}
state=$here/build/hosts/$suite

# --- the root filesystem (made once, cached by suite and package list) -------------------------
# What each root filesystem holds. bullseye: the compiler and the -dev packages of the libraries the
# plugins link, at bullseye's versions (their symbol versions are what the archives may need), and
# from bookworm only header-only packages that bullseye lacks or has too old (Eigen 3.4, the one the
# bookworm build uses; nlohmann-json; CLI11): headers carry no symbol version. No FAISS or OpenCV:
# the portable build is of the plugins alone, configured without them.
extra_sources=()
case "$suite" in
  trixie|forky) mapfile -t packages < <("$here/tools/setup.sh" --packages plugins | sort -u) ;;
  forky-bare) packages=(meshlab xvfb xauth) ;;
  *-python) packages=(python3 python3-venv python3-numpy python3-matplotlib python3-pytest)
            # bookworm's fonttools (matplotlib) takes scipy for its first alternative, and scipy pythran,
            # g++ and python3-dev: its other alternative, munkres, keeps the compiler out
            if [ "$suite" = bookworm-python ]; then packages+=(python3-munkres); fi ;;
  bullseye)
    packages=(g++ make cmake pkg-config ccache patchelf python3 binutils file xz-utils
              qtbase5-dev libqt5opengl5-dev libglew-dev libtbb-dev libsuitesparse-dev
              libeigen3-dev/bookworm nlohmann-json3-dev/bookworm libcli11-dev/bookworm)
    extra_sources=(bookworm) ;;
  bookworm-new) packages=() ;;
esac
if [ "$prepare" = 1 ]; then  # (the recipe of the first version of this script: the same cache key)
  recipe="canonform host rootfs v2: mmdebstrap --variant=apt $suite main; meshlab's Recommends; ${packages[*]}"
elif [ "$variant" != apt ]; then
  recipe="canonform host rootfs v3 $suite: mmdebstrap --variant=$variant $release main"
else
  recipe="canonform host rootfs v3 $suite: mmdebstrap --variant=apt $release main${extra_sources[*]:+ + ${extra_sources[*]}}; meshlab's Recommends; ${packages[*]}"
fi
key=$(printf '%s\n' "$recipe" | sha256sum | cut -c1-16)
lower=$cache/$suite-$key

# The machine's Debian archive URI, from its apt entries (deb822 or one-line format).
mirror_uri() {
  local uri
  uri=$(awk -v RS= '/Types:([^\n]* )?deb([ \n]|$)/ && !/security/ { n=split($0, L, "\n");
          for (i=1;i<=n;i++) if (L[i] ~ /^URIs:/) { sub(/^URIs:[ ]*/, "", L[i]); split(L[i], a, " "); print a[1]; exit } }' \
        /etc/apt/sources.list.d/*.sources 2>/dev/null | head -n 1)
  if [ -z "$uri" ] && [ -f /etc/apt/sources.list ]; then
    uri=$(awk '$1=="deb" && $0 !~ /security/ { for (i=2;i<=NF;i++) if ($i ~ /:\/\//) { print $i; exit } }' /etc/apt/sources.list)
  fi
  [ -n "$uri" ] || die "no Debian 'deb' entry in /etc/apt to take the mirror from"
  echo "$uri"
}

make_rootfs() {
  command -v mmdebstrap >/dev/null || die "mmdebstrap missing (tools/setup.sh installs it)"
  mkdir -p "$cache"
  exec 8>"$cache/.$suite-$key.lock"
  flock 8
  [ -f "$lower/.canonform-complete" ] && return 0  # made meanwhile by another run
  local uri opts=() t0=$SECONDS f c0
  read -r -a f < <(sed 's/^.*) //' "/proc/$$/stat"); c0=$((f[13] + f[14]))
  uri=$(mirror_uri)
  # testing/unstable: the mirror's Release files may be past their Valid-Until date
  case "$release" in forky) opts+=(--aptopt='Acquire::Check-Valid-Until "false"') ;; esac
  local sources=("deb $uri $release main") s
  for s in "${extra_sources[@]}"; do sources+=("deb $uri $s main"); done
  # packages from the release itself unless named as pkg/suite
  [ ${#extra_sources[@]} -eq 0 ] || opts+=(--aptopt="APT::Default-Release \"$release\"")
  log "making the $suite root filesystem in $lower (mmdebstrap, mirror $uri, ${#packages[@]} packages); this takes minutes"
  rm -rf "$lower.tmp"
  # mmdebstrap installs no Recommends; a user's `apt install meshlab` does, and MeshLab's GUI
  # complains about the plugins they serve (muparser, lib3ds, openctm, ...): install meshlab's own.
  local hook
  hook=$(mktemp)
  cat > "$hook" <<'EOF'
#!/bin/sh
set -e
chroot "$1" dpkg-query -W meshlab >/dev/null 2>&1 || exit 0
recommends=$(chroot "$1" apt-cache depends meshlab | awk '/Recommends:/ { if (alt) { alt = 0; next }
    if ($1 ~ /^\|/) alt = 1; gsub(/[<>]/, "", $2); print $2 }')
chroot "$1" env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends $recommends
EOF
  chmod +x "$hook"
  [ ${#packages[@]} -eq 0 ] || opts+=(--include="$(IFS=,; echo "${packages[*]}")")
  if ! mmdebstrap --variant="$variant" --quiet "${opts[@]}" \
        --customize-hook="$hook" \
        "$release" "$lower.tmp" "${sources[@]}" > "$cache/$suite-$key.log" 2>&1; then
    rm -f "$hook"
    tail -n 30 "$cache/$suite-$key.log" >&2
    rm -rf "$lower.tmp"
    die "mmdebstrap failed (log: $cache/$suite-$key.log)"
  fi
  rm -f "$hook"
  printf '%s\n' "$recipe" > "$lower.tmp/.canonform-recipe"
  touch "$lower.tmp/.canonform-complete"
  mv "$lower.tmp" "$lower"
  read -r -a f < <(sed 's/^.*) //' "/proc/$$/stat")
  log "root filesystem ready in $((SECONDS - t0)) s, $(( (f[13] + f[14] - c0) / $(getconf CLK_TCK) )) CPU s ($(du -sh "$lower" | cut -f1))"
}
[ -f "$lower/.canonform-complete" ] || make_rootfs
if [ "$only" = --make ]; then
  log "root filesystem ready: $lower"
  exit 0
fi

# --- the overlay for this clone, and the mounts ----------------------------------------------
mkdir -p "$state"
exec 9>"$state/.lock"
flock 9  # one run per clone and suite at a time (they share the overlay)
if [ "$(cat "$state/key" 2>/dev/null || true)" != "$key" ]; then
  rm -rf "$state/upper" "$state/work"  # made over another root filesystem
  echo "$key" > "$state/key"
fi
root=$state/root
mkdir -p "$state/upper" "$state/work" "$root"

mounted=()
cleanup() {
  local rc=$? i pid
  trap - EXIT INT TERM
  # processes still running inside (e.g. a daemon COMMAND left behind) hold the mounts
  for pid in $(ls /proc | grep -E '^[0-9]+$'); do
    [ "$(readlink "/proc/$pid/root" 2>/dev/null || true)" = "$root" ] && kill "$pid" 2>/dev/null || true
  done
  for ((i = ${#mounted[@]} - 1; i >= 0; i--)); do
    umount -R "${mounted[$i]}" 2>/dev/null || umount -R -l "${mounted[$i]}" 2>/dev/null ||
      echo "[host $suite] warning: could not unmount ${mounted[$i]}" >&2
  done
  exit "$rc"
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM
mnt() {  # mnt TARGET MOUNT-ARGS...: mount, and remember it for cleanup
  local target=$1; shift
  mount "$@" "$target"
  mounted+=("$target")
}
findmnt "$root" >/dev/null 2>&1 && umount -R -l "$root"  # left over by a killed run
mnt "$root" -t overlay overlay -o "lowerdir=$lower,upperdir=$state/upper,workdir=$state/work"
mnt "$root/proc" -t proc proc
mnt "$root/dev" --rbind /dev
mount --make-rslave "$root/dev"
mnt "$root/tmp" --bind /tmp
[ -e "$root/etc/resolv.conf" ] || { rm -f "$root/etc/resolv.conf"; : > "$root/etc/resolv.conf"; }
[ -f /etc/resolv.conf ] && mnt "$root/etc/resolv.conf" --bind /etc/resolv.conf
mkdir -p "$root$here"
mnt "$root$here" --bind "$here"
# external/ entries that link out of the tree (a worktree sharing another checkout's sources)
for l in "$here"/external/*; do
  [ -L "$l" ] || continue
  t=$(readlink -f "$l")
  case "$t" in "$here"/*) continue ;; esac
  [ -d "$t" ] || continue
  mkdir -p "$root$t"
  mnt "$root$t" --bind "$t"
  mount -o remount,bind,ro "$root$t"
done

# bullseye: a compiler cache outside the clone, kept between runs (the build passes without it)
ccache_env=()
if [ "$suite" = bullseye ] && [ "${CANONFORM_HOST_CCACHE:-1}" != 0 ]; then
  mkdir -p "$cache/ccache-$suite" "$root/var/cache/ccache"
  mnt "$root/var/cache/ccache" --bind "$cache/ccache-$suite"
  ccache_env=(CCACHE_DIR=/var/cache/ccache CCACHE_MAXSIZE=5G CCACHE_BASEDIR="$here" CCACHE_NOHASHDIR=true
              CMAKE_CXX_COMPILER_LAUNCHER=ccache CMAKE_C_COMPILER_LAUNCHER=ccache)
fi

inside() {  # runs its arguments inside, as root, with a clean environment
  local cwd=$1; shift
  chroot "$root" /usr/bin/env -i HOME=/root LANG=C.UTF-8 TERM="${TERM:-dumb}" CI="${CI:-}" ${ccache_env[@]+"${ccache_env[@]}"} \
    PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin \
    bash -c 'cd "$1" && shift && exec "$@"' inside "$cwd" "$@"
}

# --- build and install the plugins inside, by the README's commands --------------------------
if [ "$prepare" = 1 ] && [ "${CANONFORM_HOST_PREPARE:-1}" != 0 ]; then
  t0=$SECONDS
  if ! inside "$here" env CANONFORM_BUILD_DIR="$state/build" bash -c '
      set -e
      tools/build.sh --plugins >&2
      deb=$(tools/package.sh --build-dir "$CANONFORM_BUILD_DIR")
      sum=$(sha256sum "$deb" | cut -d" " -f1)
      if [ "$(cat /var/lib/canonform-installed.sha256 2>/dev/null)" != "$sum" ]; then
        echo "[host] apt-get install $deb" >&2
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --reinstall "$deb" >/dev/null
        echo "$sum" > /var/lib/canonform-installed.sha256
      fi'; then
    die "building or installing the plugins inside $suite failed"
  fi
  log "plugins built and installed ($((SECONDS - t0)) s)"
fi
[ "$only" = --prepare ] && exit 0

# --- the command ---------------------------------------------------------------------------------
cwd=$PWD
case "$cwd" in "$here"|"$here"/*|/tmp|/tmp/*) ;; *) cwd=$here ;; esac
set +e
inside "$cwd" "$@"
rc=$?
set -e
exit "$rc"
