#!/usr/bin/env bash
# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
# Set up everything CGMS needs on a Debian bookworm machine, reusing a cache when one exists:
#   1. Debian packages (compiler, CMake, Open MPI, NumPy/SciPy/matplotlib/MDAnalysis/pytest);
#   2. LAMMPS 4 Feb 2025 from Debian's trixie *source* package, built with PLUGIN, MPI and
#      OpenMP into a cache folder keyed by version and options;
#   3. the CGMS plugin (cgmsplugin.so) built against that LAMMPS, in build/ of the work tree.
# At the end it writes build/env.sh, which the run and test commands source.
#
# Environment:
#   CGMS_CACHE       cache root (default: ~/.cache/cgms)
#   LAMMPS_SOURCE_DIR, LAMMPS_BUILD_DIR
#                    use an existing LAMMPS (stable 2 Aug 2023 or newer, built with
#                    PKG_PLUGIN=on and BUILD_SHARED_LIBS=on) instead of building one
#   CGMS_SKIP_APT=1  do not call apt-get (you installed the packages yourself)
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cache=${CGMS_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/cgms}
jobs=$(nproc 2>/dev/null || echo 2)

LAMMPS_DEB_VERSION=20250204+dfsg.1-2
LAMMPS_ORIG=lammps_20250204+dfsg.1.orig.tar.xz
LAMMPS_SHA256=3671165bd52fad36734e0a9136c5bc5ecb225e03988f8c89aa13366a8b53b1c7
LAMMPS_OPTIONS="-DPKG_PLUGIN=on -DPKG_SPH=on -DPKG_MOLECULE=on -DPKG_EXTRA-PAIR=on -DBUILD_SHARED_LIBS=on -DBUILD_MPI=on -DBUILD_OMP=on -DLAMMPS_EXCEPTIONS=on -DCMAKE_BUILD_TYPE=Release"

say() { printf '[cgms setup] %s\n' "$*" >&2; }
die() { printf '[cgms setup] ERROR: %s\n' "$*" >&2; exit 1; }

# ---------------------------------------------------------------- 1. Debian packages
APT_PACKAGES=(build-essential cmake xz-utils ca-certificates openmpi-bin libopenmpi-dev
  python3 python3-numpy python3-scipy python3-matplotlib python3-mdanalysis python3-pytest
  python3-tqdm python3-mpi4py)

missing_packages() {
  local p
  for p in "${APT_PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || echo "$p"
  done
}

install_packages() {
  local missing
  missing=$(missing_packages)
  [ -z "$missing" ] && return 0
  [ "${CGMS_SKIP_APT:-0}" = 1 ] && die "missing Debian packages: $(echo $missing); install them or unset CGMS_SKIP_APT"
  local sudo=""
  [ "$(id -u)" -ne 0 ] && sudo=sudo
  say "installing Debian packages: $(echo $missing)"
  $sudo apt-get update -q >/dev/null || die "apt-get update failed"
  # shellcheck disable=SC2086
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -q --no-install-recommends $missing >/dev/null \
    || die "apt-get install failed for: $(echo $missing)"
}

# ---------------------------------------------------------------- 2. LAMMPS
# The trixie source package is fetched with a private apt configuration (its own sources
# list, lists and cache folders), built from the archive URI the machine already uses, so
# the system's apt configuration is not touched.
fetch_lammps_source() {
  local dest=$1 tarball=$cache/src/$LAMMPS_ORIG
  mkdir -p "$cache/src"
  if [ ! -f "$tarball" ] || ! echo "$LAMMPS_SHA256  $tarball" | sha256sum -c --status; then
    local aptdir=$cache/apt uri
    uri=$(sed -n 's/^URIs:[[:space:]]*//p' /etc/apt/sources.list.d/debian.sources 2>/dev/null | head -n1)
    [ -n "$uri" ] || uri=$(awk '$1=="deb"{print $2; exit}' /etc/apt/sources.list 2>/dev/null)
    [ -n "$uri" ] || die "cannot find the Debian archive URI in /etc/apt/sources.list.d/debian.sources"
    mkdir -p "$aptdir/lists/partial" "$aptdir/archives/partial"
    printf 'deb-src %s trixie main\n' "$uri" > "$aptdir/sources.list"
    local opts=(-o "Dir::Etc::SourceList=$aptdir/sources.list" -o "Dir::Etc::SourceParts=/dev/null"
      -o "Dir::State::Lists=$aptdir/lists" -o "Dir::Cache::Archives=$aptdir/archives"
      -o "Dir::Cache::pkgcache=" -o "Dir::Cache::srcpkgcache=" -o "APT::Sandbox::User=root")
    say "fetching the LAMMPS $LAMMPS_DEB_VERSION source package (Debian trixie)"
    apt-get "${opts[@]}" update -q >/dev/null 2>&1 || die "apt-get update of the trixie source index failed"
    # The .dsc of this version is missing from the archive, so apt exits non-zero after the
    # tarball arrives: judge the download by the tarball's checksum instead.
    (cd "$cache/src" && apt-get "${opts[@]}" source --download-only -q "lammps=$LAMMPS_DEB_VERSION" >/dev/null 2>&1) || true
    [ -f "$tarball" ] || die "the LAMMPS source tarball $LAMMPS_ORIG did not arrive"
    echo "$LAMMPS_SHA256  $tarball" | sha256sum -c --status \
      || { rm -f "$tarball"; die "checksum mismatch for $LAMMPS_ORIG (removed; run again)"; }
  fi
  say "unpacking LAMMPS source"
  rm -rf "$dest.tmp" && mkdir -p "$dest.tmp"
  tar -xJf "$tarball" -C "$dest.tmp" --strip-components=1
  mv "$dest.tmp" "$dest"
}

build_lammps() {
  local key src bld
  key=$(printf '%s %s' "$LAMMPS_DEB_VERSION" "$LAMMPS_OPTIONS" | sha256sum | cut -c1-12)
  src=$cache/lammps-20250204-src
  bld=$cache/lammps-20250204-$key
  if [ -f "$bld/.complete" ]; then
    LAMMPS_SOURCE_DIR=$src LAMMPS_BUILD_DIR=$bld
    return 0
  fi
  [ -d "$src/src" ] || fetch_lammps_source "$src"
  say "building LAMMPS into $bld (about 6 minutes on 2 cores; done once)"
  mkdir -p "$bld"
  # shellcheck disable=SC2086
  (cd "$bld" && cmake -S "$src/cmake" -B . $LAMMPS_OPTIONS > cmake.log 2>&1 \
    && cmake --build . -j "$jobs" > build.log 2>&1) \
    || die "LAMMPS build failed; see $bld/cmake.log and $bld/build.log"
  touch "$bld/.complete"
  LAMMPS_SOURCE_DIR=$src LAMMPS_BUILD_DIR=$bld
}

# ---------------------------------------------------------------- 3. the plugin
build_plugin() {
  local bld=$here/build
  say "building the CGMS plugin in $bld"
  cmake -S "$here" -B "$bld" -DCMAKE_BUILD_TYPE=Release \
    -DLAMMPS_SOURCE_DIR="$LAMMPS_SOURCE_DIR" -DLAMMPS_BUILD_DIR="$LAMMPS_BUILD_DIR" > "$bld.cmake.log" 2>&1 \
    || { cat "$bld.cmake.log" >&2; die "configuring the plugin failed (log above)"; }
  rm -f "$bld.cmake.log"
  cmake --build "$bld" -j "$jobs" >&2 || die "building the plugin failed (compiler output above)"
}

write_env() {
  local f=$here/build/env.sh
  cat > "$f" <<ENV
# written by tools/setup.sh: source it to use this CGMS build
export LAMMPS_SOURCE_DIR='$LAMMPS_SOURCE_DIR'
export LAMMPS_BUILD_DIR='$LAMMPS_BUILD_DIR'
export CGMS_LMP='$LAMMPS_BUILD_DIR/lmp'
export CGMS_PLUGIN='$here/build/cgmsplugin.so'
export LAMMPS_PLUGIN_PATH='$here/build'
export LD_LIBRARY_PATH='$LAMMPS_BUILD_DIR'\${LD_LIBRARY_PATH:+:\$LD_LIBRARY_PATH}
export PYTHONPATH='$here/python:$LAMMPS_SOURCE_DIR/python'\${PYTHONPATH:+:\$PYTHONPATH}
export CGMS_POTENTIALS='$here/potentials'
export LAMMPS_POTENTIALS='$here/potentials'\${LAMMPS_POTENTIALS:+:\$LAMMPS_POTENTIALS}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMP_NUM_THREADS=\${OMP_NUM_THREADS:-1}
ENV
}

install_packages
if [ -n "${LAMMPS_BUILD_DIR:-}" ]; then
  [ -n "${LAMMPS_SOURCE_DIR:-}" ] || die "LAMMPS_BUILD_DIR is set but LAMMPS_SOURCE_DIR is not"
  [ -f "$LAMMPS_SOURCE_DIR/src/lammpsplugin.h" ] \
    || die "$LAMMPS_SOURCE_DIR/src/lammpsplugin.h not found: LAMMPS_SOURCE_DIR must be a LAMMPS source tree of 2 Aug 2023 or newer"
else
  build_lammps
fi
build_plugin
write_env
say "ready: plugin $here/build/cgmsplugin.so, LAMMPS $LAMMPS_BUILD_DIR"
