#!/usr/bin/env bash
# Installs every Debian package the build, the tests, the benchmark and CI need.
# Safe to run twice: apt-get only installs what is missing, and the package index
# is refreshed only when it is older than a day (or was never fetched).
set -euo pipefail

PKGS=(
  # build
  build-essential cmake ninja-build pkg-config ccache
  # geometry kernel and subdivision (issues 3-5)
  libocct-foundation-dev libocct-modeling-data-dev libocct-modeling-algorithms-dev
  libocct-data-exchange-dev libocct-ocaf-dev libocct-visualization-dev
  libosd-dev libglm-dev libtbb-dev libdraco-dev draco
  # small well-kept libraries
  catch2 nlohmann-json3-dev libcli11-dev libfmt-dev
  # Python module (pybind11 over Debian's /usr/bin/python3, numpy arrays, pytest tests)
  python3-dev pybind11-dev python3-numpy python3-pytest
  # volume meshing: Netgen's nglib (LGPL) fills the closed solids from our surface mesh
  libnglib-dev
  # comparison benchmark and cross-checks (reference tools, not product deps)
  libcgal-dev libgmp-dev libmpfr-dev libboost-dev gmsh python3-gmsh tetgen python3-meshio freefem++
  # fuzzing and sanitizers; clang-format checks the sources (tests/code)
  clang libclang-rt-14-dev clang-format
  # misc test helpers
  time
  # browser test of the .glb (issue 6): headless Chromium + three.js served from node_modules
  chromium nodejs
  # Draco's scene/glTF headers (draco/scene/trs_matrix.h) include Eigen
  libeigen3-dev
)
# npm: Debian's package, unless a nodejs build that bundles npm (and conflicts with it) is installed
command -v npm >/dev/null 2>&1 || PKGS+=(npm)

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
# three.js from npm for the browser test of the .glb output, once the Debian packages are
# in (on every successful exit, including the "all installed" one below).
browser_deps="$(cd "$(dirname "$0")/.." && pwd)/tests/browser/install.sh"
trap 'rc=$?; if [ "$rc" -eq 0 ]; then "$browser_deps" || exit 1; fi' EXIT

missing=()
for p in "${PKGS[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PKGS[@]} packages already installed"
  exit 0
fi

stamp=/var/lib/apt/periodic/update-success-stamp
lists=$(find /var/lib/apt/lists -maxdepth 1 -name '*Packages*' -mmin -1440 2>/dev/null | head -1 || true)
if [ -z "$lists" ]; then
  $SUDO apt-get update -q
fi
echo "install-deps: installing ${missing[*]}"
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
