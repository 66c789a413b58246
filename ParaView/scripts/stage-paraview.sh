#!/usr/bin/env bash
# Stages a ParaView 5.11 prefix for building the plugin, without installing python3-paraview.
#
# Debian's paraview-dev CMake package refers to files that only python3-paraview ships (its
# bundled VTK's Python modules under lib/python3/dist-packages, the wrapping hierarchy files
# under lib/x86_64-linux-gnu/vtk/hierarchy/ParaView). python3-paraview cannot be installed next
# to python3-vtk9 and libvtk9-dev (it removes them: both ship `vtkmodules`). So this script
# downloads the package, extracts it into <dir>/python3-paraview (nothing is installed), and
# makes <dir>/prefix: a tree of symbolic links that is /usr everywhere except in those two
# folders, which come from the extracted package. CMake is configured with
#   -DParaView_DIR=<dir>/prefix/lib/x86_64-linux-gnu/cmake/paraview-5.11
# and pvbatch runs with PYTHONPATH=<dir>/python3-paraview/usr/lib/python3/dist-packages.
#
# Usage: stage-paraview.sh <dir>. Needs `paraview` and `paraview-dev` installed (install-deps.sh
# does it) and Debian's package archive (apt-get download). Does nothing when <dir> is staged.
set -euo pipefail
dir="$(mkdir -p "$1" && cd "$1" && pwd)"
multiarch="$(dpkg-architecture -qDEB_HOST_MULTIARCH 2>/dev/null || echo x86_64-linux-gnu)"
if [ -f "$dir/.staged" ]; then
  exit 0
fi
version="$(dpkg-query -W -f='${Version}' paraview-dev)"
extracted="$dir/python3-paraview"
if [ ! -d "$extracted/usr/lib/python3/dist-packages/paraview" ]; then
  rm -rf "$dir/download" "$extracted"
  mkdir -p "$dir/download"
  # the same version as paraview-dev; apt-get download runs as the _apt user when it can
  chmod 777 "$dir/download"
  (cd "$dir/download" && apt-get download "python3-paraview=$version")
  dpkg-deb -x "$dir"/download/python3-paraview_*.deb "$extracted"
fi

prefix="$dir/prefix"
rm -rf "$prefix"
mkdir -p "$prefix"
# /usr's top level, /usr/lib and the multiarch folder, each linked entry by entry (one ln
# each, thousands of entries) except the folders that are replaced
ln -s /usr/* "$prefix/" 2>/dev/null || true
rm "$prefix/lib" "$prefix/bin"
# bin: /usr/bin and the package's pvpython (which the CMake package checks for)
mkdir -p "$prefix/bin"
find /usr/bin -mindepth 1 -maxdepth 1 -exec ln -s -t "$prefix/bin" {} +
find "$extracted/usr/bin" -mindepth 1 -maxdepth 1 -exec ln -sf -t "$prefix/bin" {} +
mkdir -p "$prefix/lib/python3" "$prefix/lib/$multiarch/vtk/hierarchy"
find /usr/lib -mindepth 1 -maxdepth 1 ! -name python3 ! -name "$multiarch" \
  -exec ln -s -t "$prefix/lib" {} +
find "/usr/lib/$multiarch" -mindepth 1 -maxdepth 1 ! -name vtk ! -name cmake \
  -exec ln -s -t "$prefix/lib/$multiarch" {} +
# ParaView's CMake package is copied, not linked: its target files resolve their own real path
# and, when it is under /usr, use /usr as the prefix
mkdir -p "$prefix/lib/$multiarch/cmake"
find "/usr/lib/$multiarch/cmake" -mindepth 1 -maxdepth 1 ! -name paraview-5.11 \
  -exec ln -s -t "$prefix/lib/$multiarch/cmake" {} +
cp -r "/usr/lib/$multiarch/cmake/paraview-5.11" "$prefix/lib/$multiarch/cmake/"
ln -s "$extracted/usr/lib/python3/dist-packages" "$prefix/lib/python3/dist-packages"
# the system VTK's hierarchy stays next to ParaView's
for entry in /usr/lib/"$multiarch"/vtk/hierarchy/* "$extracted/usr/lib/$multiarch"/vtk/hierarchy/*; do
  [ -e "$prefix/lib/$multiarch/vtk/hierarchy/$(basename "$entry")" ] ||
    ln -s "$entry" "$prefix/lib/$multiarch/vtk/hierarchy/$(basename "$entry")"
done
touch "$dir/.staged"
echo "ParaView prefix staged in $prefix"
