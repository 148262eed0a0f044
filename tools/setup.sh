#!/usr/bin/env bash
# canonform set-up: installs what is missing with apt and fetches two Debian source packages into
# external/ (ignored by git). Idempotent: a second run does nothing.
#   - meshlab=2020.09+dfsg1-2 (bookworm): headers + vcglib of the installed MeshLab 2020.09, for
#     the default (float) plugins;
#   - meshlab=2022.02+dfsg1-1 (trixie): MeshLab 2022.02's source, whose meshlab-common library the
#     build compiles in double precision for the pymeshlab 2022.2 plugins (CANONFORM_MESHLAB2022).
#
#   tools/setup.sh            # as root (or with sudo available)
#   MESHLAB_SRC=/path tools/setup.sh          # use an existing MeshLab 2020.09 source tree instead
#   CANONFORM_MESHLAB2022=0 tools/setup.sh    # do not fetch MeshLab 2022.02
#
# deb-src entries are derived from the machine's own Debian 'deb' entry: no host is named here.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
MESHLAB_VERSION=2020.09+dfsg1-2
SRC_DIR="$here/external/meshlab-2020.09"
MESHLAB2022_VERSION=2022.02+dfsg1-1
MESHLAB2022_SUITE=trixie
SRC2022_DIR="$here/external/meshlab-2022.02"

PACKAGES=(
  meshlab qtbase5-dev libqt5opengl5-dev libglew-dev libeigen3-dev
  cmake g++ make dpkg-dev pkg-config
  libsuitesparse-dev libopencv-dev libgtest-dev googletest libcli11-dev nlohmann-json3-dev libtbb-dev
  xvfb xauth x11-utils xdotool imagemagick
  python3-matplotlib python3-numpy bc
)
# The sanitizer and fuzz tests (tools/sanitizer_tests.sh): clang with its ASan, UBSan and libFuzzer
# runtimes, and llvm-symbolizer for readable reports.
PACKAGES+=(clang libclang-rt-14-dev llvm)

log() { printf '[setup] %s\n' "$*"; }

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

# --- deb-src entries, derived from this machine's Debian 'deb' entry ---------------------------
# Prints "URI KEYRING" of the first plain Debian archive entry (deb822 or one-line format).
debian_uri_keyring() {
  local uri="" keyring="" f
  for f in /etc/apt/sources.list.d/*.sources; do
    [ -f "$f" ] || continue
    # first stanza that is a plain Debian archive (not the security one)
    read -r uri keyring < <(awk -v RS= '/Types:[^\n]*deb/ && !/security/ {
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

# Adds a deb-src entry for suite $1 in file $2 (main component, same archive and keyring).
add_deb_src() {
  local suite=$1 file=$2 uri keyring
  read -r uri keyring < <(debian_uri_keyring) || true
  [ -n "$uri" ] || exit 1  # debian_uri_keyring said why
  log "adding deb-src entry derived from $uri ($suite) in $file"
  {
    echo "Types: deb-src"
    echo "URIs: $uri"
    echo "Suites: $suite"
    echo "Components: main"
    [ -n "$keyring" ] && echo "Signed-By: $keyring"
  } | $SUDO tee "$file" >/dev/null
  apt_updated=0
}

tmp=""
trap '[ -n "$tmp" ] && rm -rf "$tmp"' EXIT
mkdir -p "$here/external"

# --- MeshLab 2020.09 source (headers and vcglib), unpacked under external/ -------------------
codename=$(. /etc/os-release && echo "${VERSION_CODENAME:-bookworm}")
if [ -n "${MESHLAB_SRC:-}" ]; then
  log "using MESHLAB_SRC=$MESHLAB_SRC"
elif [ -f "$SRC_DIR/src/common/interfaces.h" ] && [ -d "$SRC_DIR/vcglib/vcg" ]; then
  log "MeshLab 2020.09 source present in $SRC_DIR"
else
  if ! have_deb_src_for "$codename"; then
    add_deb_src "$codename" /etc/apt/sources.list.d/canonform-deb-src.sources
  fi
  apt_update
  log "fetching Debian source package meshlab=$MESHLAB_VERSION into external/"
  tmp=$(mktemp -d "$here/external/.fetch.XXXXXX")
  # The version is pinned: a deb-src entry for a newer suite (trixie, below) must not change it.
  ( cd "$tmp" && apt-get source -qq "meshlab=$MESHLAB_VERSION" >/dev/null )
  unpacked=$(find "$tmp" -maxdepth 1 -mindepth 1 -type d -name 'meshlab-*' | head -n 1)
  if [ -z "$unpacked" ] || [ ! -f "$unpacked/src/common/interfaces.h" ]; then
    echo "[setup] error: the source package did not unpack as expected" >&2
    exit 1
  fi
  rm -rf "$SRC_DIR"
  mv "$unpacked" "$SRC_DIR"
  rm -rf "$tmp"; tmp=""
  log "MeshLab 2020.09 source ready in $SRC_DIR"
fi

# --- MeshLab 2022.02 source (meshlab-common, vcglib), for the pymeshlab 2022.2 build ------------
if [ "${CANONFORM_MESHLAB2022:-1}" = "0" ]; then
  log "CANONFORM_MESHLAB2022=0: MeshLab 2022.02 source not fetched"
  exit 0
fi
if [ -f "$SRC2022_DIR/src/common/plugins/interfaces/filter_plugin.h" ] && [ -d "$SRC2022_DIR/src/vcglib/vcg" ]; then
  log "MeshLab 2022.02 source present in $SRC2022_DIR"
  exit 0
fi
if ! have_deb_src_for "$MESHLAB2022_SUITE"; then
  add_deb_src "$MESHLAB2022_SUITE" /etc/apt/sources.list.d/canonform-deb-src-$MESHLAB2022_SUITE.sources
fi
apt_update
versions=$(apt-cache showsrc meshlab | sed -n 's/^Version: //p')
if ! printf '%s\n' "$versions" | grep -qxF "$MESHLAB2022_VERSION"; then
  echo "[setup] error: no source package meshlab=$MESHLAB2022_VERSION in the apt indices (suite $MESHLAB2022_SUITE);" >&2
  echo "[setup] versions seen: $(echo $versions)" >&2
  exit 1
fi
log "fetching Debian source package meshlab=$MESHLAB2022_VERSION ($MESHLAB2022_SUITE) into external/"
tmp=$(mktemp -d "$here/external/.fetch.XXXXXX")
( cd "$tmp" && apt-get source -qq --download-only "meshlab=$MESHLAB2022_VERSION" ) > "$tmp/apt.log" 2>&1 || true
dsc="$tmp/meshlab_${MESHLAB2022_VERSION}.dsc"
orig=$(find "$tmp" -maxdepth 1 -name "meshlab_${MESHLAB2022_VERSION%-*}.orig.tar.*" | head -n 1)
if [ -f "$dsc" ]; then
  ( cd "$tmp" && dpkg-source -q -x "$(basename "$dsc")" src >/dev/null )
  unpacked="$tmp/src"
elif [ -n "$orig" ]; then
  # Some mirrors serve the upstream tarball but not the .dsc/.debian.tar.xz of this revision.
  # apt-get verified the tarball against the signed index; check it again, then unpack it alone.
  want=$(apt-cache showsrc meshlab | awk -v v="$MESHLAB2022_VERSION" -v f="$(basename "$orig")" '
      /^Package:/ { inv=0 } $0 == "Version: " v { inv=1 }
      /^Checksums-Sha256:/ { c=1; next } /^[^ ]/ { c=0 } inv && c && $3==f { print $1; exit }')
  have=$(sha256sum "$orig" | cut -d' ' -f1)
  if [ -z "$want" ] || [ "$want" != "$have" ]; then
    echo "[setup] error: $(basename "$orig"): SHA-256 $have does not match the index ($want)" >&2
    exit 1
  fi
  log "warning: the mirror has no .dsc/.debian.tar.xz for meshlab=$MESHLAB2022_VERSION"
  log "         ($(grep -c 404 "$tmp/apt.log" || true) files not found); unpacking the upstream tarball"
  log "         $(basename "$orig") (SHA-256 checked against the index), without Debian's patches"
  mkdir "$tmp/src"
  tar -xf "$orig" -C "$tmp/src" --strip-components=1
  unpacked="$tmp/src"
else
  cat "$tmp/apt.log" >&2
  echo "[setup] error: could not download the source package meshlab=$MESHLAB2022_VERSION" >&2
  exit 1
fi
if [ ! -f "$unpacked/src/common/plugins/interfaces/filter_plugin.h" ] || [ ! -d "$unpacked/src/vcglib/vcg" ]; then
  echo "[setup] error: the MeshLab 2022.02 source did not unpack as expected" >&2
  exit 1
fi
rm -rf "$SRC2022_DIR"
mv "$unpacked" "$SRC2022_DIR"
log "MeshLab 2022.02 source ready in $SRC2022_DIR"
