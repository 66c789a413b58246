#!/usr/bin/env bash
# Installs what PerceptualLOD needs on Debian bookworm (run as root). Skips apt when every
# package is already there, so it is fast and works offline on a prepared machine.
set -euo pipefail
packages=(
  cmake ninja-build g++ pkg-config
  libvtk9-dev python3-vtk9 python3-numpy python3-matplotlib mpi-default-dev
  libeigen3-dev libgtest-dev libbenchmark-dev libmeshoptimizer-dev libzstd-dev
  xvfb xauth libgl1-mesa-dri
  clang-14 libclang-rt-14-dev clang-format-14 python3-skimage
  # the ParaView plugin (ParaView/): ParaView 5.11 and its development files. Not
  # python3-paraview: it removes python3-vtk9 and libvtk9-dev (both ship vtkmodules);
  # ParaView/scripts/stage-paraview.sh extracts it into the plugin's build tree instead.
  paraview paraview-dev openmpi-bin
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "Installing: ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  echo "All packages already installed."
fi
# python3-paraview, installed system-wide by hand, would have removed VTK 9.1's Python
for p in python3-vtk9 libvtk9-dev; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    echo "error: $p is not installed (python3-paraview replaces it; remove python3-paraview and" \
      "run this script again)" >&2
    exit 1
  fi
done
