#!/usr/bin/env bash
# Install, build and run every test (C++ GoogleTest and Python) with CTest.
# Tests that need ../shared/data (the Stanford scans) skip when it is absent.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh -DPLOD_WARNINGS_AS_ERRORS=ON
ctest --test-dir build --output-on-failure -j2
