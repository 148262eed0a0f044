#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# canonform set-up: installs what is missing with apt, finds which MeshLab the system packages,
# and fetches the Debian source packages the build needs into external/ (ignored by git).
# Idempotent: a second run does nothing. Works on Debian bookworm, trixie and forky/sid:
#
#   installed MeshLab (apt)        source fetched                 plugins built (tools/build.sh)
#   2020.09 float (bookworm)       meshlab=2020.09+dfsg1-2        MeshLab 2020.09, float
#   2022.02 float (trixie)         meshlab 2022.02+dfsg1 (trixie) MeshLab 2022.02, float
#   2025.07 float (forky, sid)     meshlab 2025.07~dfsg (forky)   MeshLab 2025.07, float
#
# and, on bookworm, for the pymeshlab builds (double precision, meshlab-common compiled here):
#   meshlab 2022.02+dfsg1 (suite trixie)  pymeshlab 2022.2   (CANONFORM_MESHLAB2022=0 skips it)
#   meshlab 2025.07~dfsg  (suite forky)   pymeshlab 2025.7   (CANONFORM_MESHLAB2025=0 skips it)
# (elsewhere these are off unless set to 1).
#
# PURPOSE says what the set-up is for, and so what it installs and fetches (tools/build.sh passes
# the purpose of its build):
#   plugins   the plugins (and canonform-meshlab) alone and their Debian package: tools/build.sh
#             --plugins, tools/package.sh; the installed MeshLab's source only
#   example   README command 1 (tools/run_example.sh): plugins' packages plus the canonform tool's
#             (FAISS; not OpenCV, whose SIFT is only for comparison); the installed MeshLab's source only
#   all       (default) every build and test, README command 2: example's packages, the tests'
#             (GoogleTest, ImageMagick, ...) and the Python module's; on bookworm also the test
#             tools (mmdebstrap, qemu-user, Slurm, clang, MkDocs, Chromium), the pymeshlab
#             builds' MeshLab sources; with CANONFORM_WINDOWS=1 also the Windows build's packages
#             (its tests are not in the default run: docs/testing.md, "Windows")
#   windows   the Windows cross build alone (tools/build.sh --windows): MinGW-w64, Wine, the
#             header-only libraries and googletest's source; no MeshLab
#
#   tools/setup.sh [PURPOSE]       # as root (or with sudo available)
#   tools/setup.sh --packages [PURPOSE]   # print the apt packages PURPOSE needs on every system, one
#                                  # a line, and exit (without bookworm's test tools)
#   tools/setup.sh --meshlab       # print the installed MeshLab's version (2020.09, 2022.02, 2025.07)
#   MESHLAB_SRC=/path tools/setup.sh   # use an existing MeshLab 2020.09 source tree instead
#
# deb-src entries are derived from the machine's own Debian 'deb' entry: no host is named here.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)

# The plugins and canonform-meshlab (tools/build.sh --plugins) and their package (dpkg-shlibdeps),
# run headless under Xvfb; the MeshLab source fetched below (dpkg-source, xz: neither is on a Debian
# as its installer leaves it).
PLUGINS=(meshlab qtbase5-dev libqt5opengl5-dev libglew-dev libeigen3-dev cmake g++ make pkg-config
         libcli11-dev nlohmann-json3-dev libtbb-dev xvfb xauth dpkg-dev xz-utils)
# The canonform tool and the retrieval runs: FAISS's k-means (on OpenBLAS).
TOOL=(libfaiss-dev libopenblas0-pthread)
# The tool's `opencv` SIFT extractor, kept for comparison (tests, benchmarks); not for command 1.
OPENCV=(libopencv-dev)
# The tests and the scripts of tools/: GoogleTest, X utilities, ImageMagick, numpy and matplotlib, bc.
TESTS=(libgtest-dev googletest x11-utils xdotool imagemagick python3-matplotlib python3-numpy bc)
# The Windows build (tools/build.sh --windows, docs/windows.md): MinGW-w64's GCC 12 with POSIX
# threads, Wine 8 to run its programs (the 64-bit loader alone runs console programs headless: no X
# server, no 32-bit Wine), the host's header-only libraries and googletest's source.
WINDOWS=(g++-mingw-w64-x86-64-posix wine64 cmake make libeigen3-dev libcli11-dev nlohmann-json3-dev googletest
         python3)

codename=$(. /etc/os-release && echo "${VERSION_CODENAME:-bookworm}")

# The MeshLab the system has: upstream version of Debian's meshlab package (2020.09, 2022.02, ...).
installed_meshlab() {
  local v
  v=$(dpkg-query -W -f='${Version}' meshlab 2>/dev/null) || return 1
  v=${v#*:}
  echo "${v%%[+~-]*}"
}

usage() { echo "usage: $0 [plugins|example|all|windows] | --packages [plugins|example|all|windows] | --meshlab" >&2; exit 2; }
list_only=0
case "${1:-}" in
  --packages) list_only=1; shift ;;
  --meshlab) installed_meshlab || { echo "meshlab is not installed" >&2; exit 1; }; exit 0 ;;
esac
default_purpose=all
[ "${CANONFORM_PLUGINS_ONLY:-0}" = 1 ] && default_purpose=plugins
purpose=${1:-$default_purpose}
case "$purpose" in
  plugins) PACKAGES=("${PLUGINS[@]}") ;;
  example) PACKAGES=("${PLUGINS[@]}" "${TOOL[@]}") ;;
  all) PACKAGES=("${PLUGINS[@]}" "${TOOL[@]}" "${OPENCV[@]}" "${TESTS[@]}") ;;
  windows) PACKAGES=("${WINDOWS[@]}") ;;
  *) usage ;;
esac
[ $# -le 1 ] || usage
if [ "$list_only" = 1 ]; then printf '%s\n' "${PACKAGES[@]}"; exit 0; fi

# Purpose all only: the test tools, and the Python module.
if [ "$purpose" = all ]; then
  # The tools/host.sh root filesystems (trixie, forky) are made with Debian's mmdebstrap, from
  # bookworm (the tests run there); not needed inside those root filesystems.
  if [ "$codename" = bookworm ] && [ "${CANONFORM_HOSTS:-1}" != 0 ]; then
    PACKAGES+=(mmdebstrap)
  fi
  # The CPU matrix (tests/e2e/cpu_matrix_test.sh, docs/cpu.md) runs the tests as other x86-64 CPUs
  # with Debian's qemu-user (qemu-x86_64 -cpu MODEL); the tests are skipped without it.
  if [ "$codename" = bookworm ] && [ "${CANONFORM_CPU_MATRIX:-1}" != 0 ]; then
    PACKAGES+=(qemu-user)
  fi
  # The Slurm test cluster (tools/slurm_cluster.sh: `canonform slurm` end to end) runs on bookworm:
  # a one-node slurmctld + slurmd with munge authentication; not needed in the host root filesystems.
  if [ "$codename" = bookworm ] && [ "${CANONFORM_SLURM_TESTS:-1}" != 0 ]; then
    PACKAGES+=(slurm-wlm munge)
  fi
  # The sanitizer and fuzz tests (tools/sanitizer_tests.sh) run on bookworm too: clang with its ASan,
  # UBSan and libFuzzer runtimes (libclang-rt-dev, the default clang's), llvm-symbolizer for reports.
  if [ "$codename" = bookworm ] && [ "${CANONFORM_SANITIZER_TESTS:-1}" != 0 ]; then
    PACKAGES+=(clang libclang-rt-dev llvm)
  fi
  # The Windows build's tests (tests/windows/, ctest -L windows) run on bookworm; not needed in the
  # host root filesystems.
  if [ "$codename" = bookworm ] && [ "${CANONFORM_WINDOWS:-0}" = 1 ]; then
    PACKAGES+=("${WINDOWS[@]}")
  fi

  # The style check (tools/check_style.sh) runs on bookworm: the tree is formatted by its clang-format.
  if [ "$codename" = bookworm ]; then
    PACKAGES+=(clang-format)
  fi

  # The documentation's tests (tests/docs_test.py) run on bookworm: MkDocs with mkdocs-material builds
  # the site (docs/, mkdocs.yml) and headless Chromium opens it; not needed in the host root filesystems.
  if [ "$codename" = bookworm ] && [ "${CANONFORM_DOCS_TESTS:-1}" != 0 ]; then
    PACKAGES+=(mkdocs mkdocs-material chromium)
  fi
  # The Python module (python/, docs/python.md): pybind11, and what `pip install .` and its tests
  # use - Debian's Python with its headers, setuptools and wheel (the build backend, no PyPI), pip and
  # venv, pytest. Not with CANONFORM_PYTHON=0.
  if [ "${CANONFORM_PYTHON:-1}" != 0 ]; then
    PACKAGES+=(pybind11-dev python3-dev python3-setuptools python3-wheel python3-pip python3-venv python3-pytest)
  fi
fi

log() { printf '[setup] %s\n' "$*"; }
die() { printf '[setup] error: %s\n' "$*" >&2; exit 1; }

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; fi
fi

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

apt_updated=0
apt_update() {
  if [ "$apt_updated" -eq 0 ]; then
    $SUDO apt-get update -qq
    apt_updated=1
  fi
}

if [ "${#missing[@]}" -gt 0 ]; then
  if [ "$(id -u)" -ne 0 ] && [ -z "$SUDO" ]; then
    echo "[setup] error: missing packages: ${missing[*]}" >&2
    echo "[setup] run this script as root, or ask an administrator to install them." >&2
    exit 1
  fi
  log "installing: ${missing[*]}"
  apt_update
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
else
  log "all packages present"
fi

host_meshlab=none
[ "$purpose" = windows ] || host_meshlab=$(installed_meshlab) || die "Debian's meshlab package did not install"
case "$host_meshlab" in
  none) ;;
  2020.09|2022.02|2025.07) log "MeshLab $host_meshlab (Debian $codename) found: building its plugins" ;;
  *) die "MeshLab $host_meshlab (Debian's meshlab package): no plugin API of this project matches it (2020.09, 2022.02 or 2025.07)" ;;
esac

# --- deb-src entries, derived from this machine's Debian 'deb' entry ---------------------------
# Prints "URI KEYRING" of the first plain Debian archive entry (deb822 or one-line format).
debian_uri_keyring() {
  local uri="" keyring="" f
  for f in /etc/apt/sources.list.d/*.sources; do
    [ -f "$f" ] || continue
    # first stanza that is a plain Debian archive (not the security one)
    read -r uri keyring < <(awk -v RS= '/Types:([^\n]* )?deb([ \n]|$)/ && !/security/ {
        u=""; k="";
        n=split($0, L, "\n");
        for (i=1;i<=n;i++) { if (L[i] ~ /^URIs:/) { sub(/^URIs:[ ]*/, "", L[i]); split(L[i], a, " "); u=a[1] }
                             if (L[i] ~ /^Signed-By:/) { sub(/^Signed-By:[ ]*/, "", L[i]); k=L[i] } }
        if (u != "") { print u, k; exit } }' "$f") || true
    [ -n "$uri" ] && break
  done
  if [ -z "$uri" ] && [ -f /etc/apt/sources.list ]; then
    uri=$(awk '$1=="deb" && $0 !~ /security/ { for (i=2;i<=NF;i++) if ($i ~ /:\/\//) { print $i; exit } }' /etc/apt/sources.list)
  fi
  if [ -z "$uri" ]; then
    echo "[setup] error: no Debian 'deb' entry found to derive a deb-src entry from" >&2
    exit 1
  fi
  echo "$uri $keyring"
}

# True if some deb-src entry names suite $1.
have_deb_src_for() {
  local suite=$1
  grep -qsE "^deb-src .*[[:space:]]$suite([[:space:]]|$)" /etc/apt/sources.list /etc/apt/sources.list.d/*.list && return 0
  local f
  for f in /etc/apt/sources.list.d/*.sources; do
    [ -f "$f" ] || continue
    awk -v RS= -v s="$suite" '/Types:[^\n]*deb-src/ { if (match($0, /Suites:[^\n]*/)) { n=split(substr($0, RSTART+7, RLENGTH-7), a, " ");
         for (i=1;i<=n;i++) if (a[i]==s) found=1 } } END { exit !found }' "$f" && return 0
  done
  return 1
}

# Adds a deb-src entry for suite $1 (main component, same archive and keyring) in
# sources.list.d/canonform-deb-src[-SUITE].sources. Debian's testing and unstable Release files
# can be past their Valid-Until date on a mirror snapshot: for those suites the entry says
# Check-Valid-Until: no (for that entry only), unless the suite is the machine's own: apt refuses
# two entries for one archive and suite that disagree on it, and the machine's own entry decides.
add_deb_src() {
  local suite=$1 file uri keyring
  file=/etc/apt/sources.list.d/canonform-deb-src-$suite.sources
  [ "$suite" = "$codename" ] && [ "$suite" = bookworm ] && file=/etc/apt/sources.list.d/canonform-deb-src.sources
  read -r uri keyring < <(debian_uri_keyring) || true
  [ -n "$uri" ] || exit 1  # debian_uri_keyring said why
  log "adding deb-src entry derived from $uri ($suite) in $file"
  {
    echo "Types: deb-src"
    echo "URIs: $uri"
    echo "Suites: $suite"
    echo "Components: main"
    [ -n "$keyring" ] && echo "Signed-By: $keyring"
    case "$suite" in forky|sid|testing|unstable) [ "$suite" = "$codename" ] || echo "Check-Valid-Until: no" ;; esac
  } | $SUDO tee "$file" >/dev/null
  apt_updated=0
}

tmp=""
trap '[ -n "$tmp" ] && rm -rf "$tmp"' EXIT
mkdir -p "$here/external"

# fetch_source UPSTREAM SUITE DEST CHECK...: Debian's meshlab source of upstream version UPSTREAM
# (e.g. 2022.02+dfsg1: any Debian revision) from SUITE, unpacked into DEST; CHECK... are paths
# below DEST that must exist afterwards. Unpacks the .dsc (with Debian's patches) when the mirror
# serves it; some mirrors serve only the upstream tarball of a revision (404 for the .dsc and
# .debian.tar.xz): then the tarball alone, after checking its SHA-256 against the signed index.
fetch_source() {
  local upstream=$1 suite=$2 dest=$3; shift 3
  local c ok=1
  for c in "$@"; do [ -e "$dest/$c" ] || ok=0; done
  if [ "$ok" = 1 ]; then log "MeshLab ${upstream%%[+~]*} source present in $dest"; return 0; fi
  if ! have_deb_src_for "$suite"; then add_deb_src "$suite"; fi
  apt_update
  local versions version
  versions=$(apt-cache showsrc meshlab | sed -n 's/^Version: //p' | sort -u)
  # the newest Debian revision of that upstream version in the indices
  version=$(printf '%s\n' "$versions" | grep -F "$upstream-" | sort -V | tail -n 1 || true)
  if [ -z "$version" ]; then
    echo "[setup] error: no source package meshlab=$upstream-* in the apt indices (suite $suite);" >&2
    echo "[setup] versions seen: $(echo $versions)" >&2
    exit 1
  fi
  log "fetching Debian source package meshlab=$version ($suite) into external/"
  tmp=$(mktemp -d "$here/external/.fetch.XXXXXX")
  ( cd "$tmp" && apt-get source -qq --download-only "meshlab=$version" ) > "$tmp/apt.log" 2>&1 || true
  local dsc="$tmp/meshlab_${version#*:}.dsc" orig unpacked
  orig=$(find "$tmp" -maxdepth 1 -name "meshlab_${upstream}.orig.tar.*" | head -n 1)
  if [ -f "$dsc" ] && ( cd "$tmp" && dpkg-source -q -x "$(basename "$dsc")" src >/dev/null 2>&1 ); then
    unpacked="$tmp/src"
  elif [ -n "$orig" ]; then
    # apt-get verified the tarball against the signed index; check it again, then unpack it alone.
    local want have
    want=$(apt-cache showsrc meshlab | awk -v v="$version" -v f="$(basename "$orig")" '
        /^Package:/ { inv=0 } $0 == "Version: " v { inv=1 }
        /^Checksums-Sha256:/ { c=1; next } /^[^ ]/ { c=0 } inv && c && $3==f { print $1; exit }')
    have=$(sha256sum "$orig" | cut -d' ' -f1)
    if [ -z "$want" ] || [ "$want" != "$have" ]; then
      die "$(basename "$orig"): SHA-256 $have does not match the index ($want)"
    fi
    log "warning: the mirror has no .dsc/.debian.tar.xz for meshlab=$version"
    log "         ($(grep -c 404 "$tmp/apt.log" || true) files not found); unpacking the upstream tarball"
    log "         $(basename "$orig") (SHA-256 $have, as in the signed index), without Debian's patches"
    mkdir "$tmp/src"
    tar -xf "$orig" -C "$tmp/src" --strip-components=1
    unpacked="$tmp/src"
  else
    cat "$tmp/apt.log" >&2
    die "could not download the source package meshlab=$version"
  fi
  for c in "$@"; do
    [ -e "$unpacked/$c" ] || die "the MeshLab $upstream source did not unpack as expected ($c missing)"
  done
  rm -rf "$dest"
  mv "$unpacked" "$dest"
  rm -rf "$tmp"; tmp=""
  log "MeshLab ${upstream%%[+~]*} source ready in $dest"
}

want2020=0; want2022=0; want2025=0
pymeshlab=0  # the pymeshlab builds' sources on bookworm: for purpose all only
[ "$purpose" = all ] && pymeshlab=1
case "$host_meshlab" in
  2020.09) want2020=1; want2022=${CANONFORM_MESHLAB2022:-$pymeshlab}; want2025=${CANONFORM_MESHLAB2025:-$pymeshlab} ;;
  2022.02) want2022=1; want2025=${CANONFORM_MESHLAB2025:-0} ;;
  2025.07) want2025=1; want2022=${CANONFORM_MESHLAB2022:-0} ;;
esac

# MeshLab 2020.09 (bookworm): headers and vcglib of the installed MeshLab.
if [ "$want2020" = 1 ]; then
  if [ -n "${MESHLAB_SRC:-}" ]; then
    log "using MESHLAB_SRC=$MESHLAB_SRC"
  else
    fetch_source 2020.09+dfsg1 bookworm "$here/external/meshlab-2020.09" src/common/interfaces.h vcglib/vcg/complex/complex.h
  fi
fi
# MeshLab 2022.02 (trixie): the installed MeshLab's headers on trixie; meshlab-common in double for
# pymeshlab 2022.2 on bookworm.
if [ "$want2022" = 1 ]; then
  fetch_source 2022.02+dfsg1 trixie "$here/external/meshlab-2022.02" \
    src/common/plugins/interfaces/filter_plugin.h src/vcglib/vcg/complex/complex.h
fi
# MeshLab 2025.07 (forky): the installed MeshLab's headers on forky; meshlab-common in double for
# pymeshlab 2025.7 on bookworm.
if [ "$want2025" = 1 ]; then
  fetch_source 2025.07~dfsg forky "$here/external/meshlab-2025.07" \
    src/common/plugins/interfaces/filter_plugin.h src/vcglib/vcg/complex/complex.h
fi

