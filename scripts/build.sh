#!/usr/bin/env bash
# Configures and builds PerceptualLOD into ./build (Release, Ninja, Debian's /usr/bin/python3).
# PLOD_BUILD_DIR=<dir> builds another tree (the test command's sanitizer tree: build-asan).
set -euo pipefail
cd "$(dirname "$0")/.."
dir="${PLOD_BUILD_DIR:-build}"
cmake -S . -B "$dir" -G Ninja -DPython3_EXECUTABLE=/usr/bin/python3 "$@"
cmake --build "$dir"
