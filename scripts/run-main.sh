#!/usr/bin/env bash
# The main job: install, build, then render a built-in generated model with the perceptual LOD
# along a scripted path (translation, zoom, rotation), offscreen under Xvfb. It prints each
# frame's figures and writes perceptual_lod_output/: frames.csv, PNG frames, and compare_*.png
# (full resolution left, LOD right). Extra arguments go to the viewer (a model file, --frames N,
# --mode tmm, ...). Without --offscreen and with a display, the viewer is interactive.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
./build/bin/PerceptualLODMain
xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" \
  ./build/bin/PerceptualLODViewer --offscreen --out perceptual_lod_output "$@"
