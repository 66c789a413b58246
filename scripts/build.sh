#!/usr/bin/env bash
# Configures and builds PerceptualLOD into ./build (Release, Ninja, Debian's /usr/bin/python3).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -G Ninja -DPython3_EXECUTABLE=/usr/bin/python3 "$@"
cmake --build build
