#!/usr/bin/env bash
# The main job: install, build, then run PerceptualLOD on a built-in generated model.
# Extra arguments go to the example program (for instance a model file).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
./build/bin/PerceptualLODMain "$@"
