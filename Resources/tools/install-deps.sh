#!/usr/bin/env bash
# Installs every Debian 12 package vdmesh needs to build, test and check its
# outputs. Idempotent: quick when everything is there.
set -euo pipefail

PACKAGES=(
  # build
  cmake g++ make pkg-config
  # core
  libcgal-dev libgmp-dev libmpfr-dev libboost-dev libeigen3-dev libtbb-dev libglpk-dev zlib1g-dev liblz4-dev liblzma-dev
  # CAD
  libocct-data-exchange-dev libocct-modeling-algorithms-dev libocct-modeling-data-dev
  libocct-foundation-dev libocct-ocaf-dev
  # peer mesher
  libtet1.5-dev tetgen
  # tests, fuzzing, Python module
  libgtest-dev clang libclang-rt-14-dev pybind11-dev python3-dev python3-numpy
  # third-party checkers of our outputs
  gmsh python3-gmsh python3-meshio python3-vtk9 calculix-ccx
  # FreeCAD workbench tests
  freecad xvfb xauth
)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install-deps: done"
