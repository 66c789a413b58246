#!/usr/bin/env bash
# Builds the ParaView plugin into ./build-paraview (or PLOD_PARAVIEW_BUILD_DIR): stages
# ParaView's prefix inside the build tree (python3-paraview extracted there, nothing installed;
# see stage-paraview.sh), configures against it and builds. Extra arguments go to CMake.
# Needs paraview and paraview-dev (scripts/install-deps.sh installs them).
set -euo pipefail
cd "$(dirname "$0")/../.."
dir="${PLOD_PARAVIEW_BUILD_DIR:-build-paraview}"
mkdir -p "$dir"
bash ParaView/scripts/stage-paraview.sh "$dir/paraview-stage"
multiarch="$(dpkg-architecture -qDEB_HOST_MULTIARCH 2>/dev/null || echo x86_64-linux-gnu)"
cmake -S ParaView -B "$dir" -G Ninja \
  -DParaView_DIR="$(cd "$dir" && pwd)/paraview-stage/prefix/lib/$multiarch/cmake/paraview-5.11" \
  -DPython3_EXECUTABLE=/usr/bin/python3 "$@"
cmake --build "$dir"
echo "Plugin built: PV_PLUGIN_PATH=$(cd "$dir" && pwd)/lib/paraview-5.11/plugins/PerceptualLOD"
