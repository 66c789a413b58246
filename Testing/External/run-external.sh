#!/usr/bin/env bash
# The external-consumer test (issue 11): installs this build into a fresh prefix, builds
# Testing/External against it with find_package(PerceptualLOD), runs the program (under
# xvfb-run when there is no display), imports the Python package from the prefix, and runs the
# installed programs.
#   run-external.sh <build-dir> <work-dir>
set -euo pipefail
build="$1"
work="$2"
here="$(cd "$(dirname "$0")" && pwd)"
rm -rf "$work"
mkdir -p "$work"
prefix="$work/prefix"
cmake --install "$build" --prefix "$prefix" > "$work/install.log"
test -f "$prefix/lib/cmake/PerceptualLOD/PerceptualLODConfig.cmake"
cmake -S "$here" -B "$work/consumer" -G Ninja -DCMAKE_PREFIX_PATH="$prefix" \
  -DCMAKE_BUILD_TYPE=Release > "$work/configure.log" 2>&1 || { cat "$work/configure.log"; exit 1; }
cmake --build "$work/consumer" > "$work/build.log" 2>&1 || { cat "$work/build.log"; exit 1; }
run=()
if [ -z "${DISPLAY:-}" ] && command -v xvfb-run > /dev/null; then
  run=(xvfb-run -a -s "-screen 0 1280x1024x24 -noreset")
fi
"${run[@]}" "$work/consumer/consumer" "$work/consumer.plod"
PYTHONPATH="$prefix/lib/python3/dist-packages" /usr/bin/python3 -c \
  "from perceptual_lod import vtkPerceptualLODActor, vtkMultiscaleOctreeReader; r = vtkMultiscaleOctreeReader(); r.SetFileName('$work/consumer.plod'); r.Update(); print('python: octree of', r.GetOutput().GetNumberOfNodes(), 'nodes')"
"$prefix/bin/PerceptualLODMain" "$work/consumer.plod" | head -1
echo "external consumer: ok"
