#!/usr/bin/env bash
# canonform set-up: installs what is missing with apt and fetches the MeshLab 2020.09 source
# package (headers + vcglib) into external/. Idempotent: a second run does nothing.
#
#   tools/setup.sh            # as root (or with sudo available)
#   MESHLAB_SRC=/path tools/setup.sh   # use an existing MeshLab 2020.09 source tree instead
#
# The deb-src entry is derived from the machine's own Debian 'deb' entry: no host is named here.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
MESHLAB_VERSION=2020.09+dfsg1-2
SRC_DIR="$here/external/meshlab-2020.09"

PACKAGES=(
  meshlab qtbase5-dev libqt5opengl5-dev libglew-dev libeigen3-dev
  cmake g++ make dpkg-dev pkg-config
  libsuitesparse-dev libopencv-dev libgtest-dev googletest
  xvfb xauth x11-utils xdotool imagemagick
  python3-matplotlib python3-numpy bc
)

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

# --- MeshLab 2020.09 source (headers and vcglib), unpacked under external/ -------------------
if [ -n "${MESHLAB_SRC:-}" ]; then
  log "using MESHLAB_SRC=$MESHLAB_SRC"
  exit 0
fi
if [ -f "$SRC_DIR/src/common/interfaces.h" ] && [ -d "$SRC_DIR/vcglib/vcg" ]; then
  log "MeshLab source present in $SRC_DIR"
  exit 0
fi

# Derive a deb-src entry from the first Debian 'deb' entry of this machine (deb822 or one-line).
codename=$(. /etc/os-release && echo "${VERSION_CODENAME:-bookworm}")
srcfile=/etc/apt/sources.list.d/canonform-deb-src.sources
if ! grep -rqsE '^(Types:.*deb-src|deb-src )' /etc/apt/sources.list /etc/apt/sources.list.d/; then
  uri="" ; keyring=""
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
  log "adding deb-src entry derived from $uri ($codename)"
  {
    echo "Types: deb-src"
    echo "URIs: $uri"
    echo "Suites: $codename"
    echo "Components: main"
    [ -n "$keyring" ] && echo "Signed-By: $keyring"
  } | $SUDO tee "$srcfile" >/dev/null
  apt_updated=0
fi
apt_update

log "fetching Debian source package meshlab=$MESHLAB_VERSION into external/"
mkdir -p "$here/external"
tmp=$(mktemp -d "$here/external/.fetch.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
( cd "$tmp" && apt-get source -qq "meshlab=$MESHLAB_VERSION" >/dev/null )
unpacked=$(find "$tmp" -maxdepth 1 -mindepth 1 -type d -name 'meshlab-*' | head -n 1)
if [ -z "$unpacked" ] || [ ! -f "$unpacked/src/common/interfaces.h" ]; then
  echo "[setup] error: the source package did not unpack as expected" >&2
  exit 1
fi
rm -rf "$SRC_DIR"
mv "$unpacked" "$SRC_DIR"
log "MeshLab source ready in $SRC_DIR"
