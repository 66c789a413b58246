#!/usr/bin/env bash
# Install, build and run every test (C++ GoogleTest and Python) with CTest; then build the C++
# tests again with AddressSanitizer and UndefinedBehaviorSanitizer and run them.
# Tests that need ../shared/data (the Stanford scans) skip when it is absent.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
# every C++ file formatted as .clang-format (VTK's style) says
bash scripts/check-format.sh
bash scripts/build.sh -DPLOD_WARNINGS_AS_ERRORS=ON
ctest --test-dir build --output-on-failure -j2

# The VTK-free kernels on their own: configured without VTK, built, and their tests run (one of
# them checks that the test programs link no VTK library). About a minute.
cmake -S . -B build-core -G Ninja -DPLOD_CORE_ONLY=ON -DPLOD_WARNINGS_AS_ERRORS=ON
cmake --build build-core
ctest --test-dir build-core --output-on-failure -j2

# The ParaView plugin (ParaView/README.md): built against ParaView 5.11 in build-paraview (its
# prefix staged there, python3-paraview extracted, nothing installed system-wide) and its pvbatch
# tests run, on one rank and on two MPI ranks.
bash ParaView/scripts/build-plugin.sh -DPLOD_WARNINGS_AS_ERRORS=ON
ctest --test-dir build-paraview --output-on-failure

# Sanitizer stage (CI runs it; PLOD_SKIP_SANITIZE=1 skips it for a quicker local run). The tree
# build-asan is RelWithDebInfo without NDEBUG (so the kernels' debug asserts are checked too)
# with PLOD_SANITIZE=ON: every target of this project (kernels,
# modules, tests) is instrumented with ASan, LeakSanitizer and UBSan; VTK and the other
# libraries are not. Any report fails its test: UBSan aborts on the first one, LSan checks at
# exit. allocator_may_return_null=1 lets an impossible allocation fail as it does without ASan
# (a bad-input test hands VTK's STL reader a count that asks for 25 GB). Left out: the Python
# tests (no wrapping here: python3 is not instrumented), and the fuzzing and installed-package
# tests, which the first stage runs (the fuzz tests build their own ASan/UBSan tree with clang).
# The rendering tests preload Mesa's driver (Rendering/Testing/Cxx/CMakeLists.txt says why).
# Here (2 cores, shared with other jobs) it took 5.5 to 9 min to build and 4.5 to 9 min to test,
# depending on the load (the longest test, PointCloudBecomesAClosedOrientedSurface, runs
# 4 to 7 times slower than in the first stage); the whole command took 29 min under load.
if [ "${PLOD_SKIP_SANITIZE:-0}" != 0 ]; then
  echo "PLOD_SKIP_SANITIZE=${PLOD_SKIP_SANITIZE}: sanitizer stage skipped"
  exit 0
fi
PLOD_BUILD_DIR=build-asan bash scripts/build.sh -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -g" \
  -DPLOD_SANITIZE=ON -DPLOD_WRAP_PYTHON=OFF -DPLOD_BUILD_BENCHMARKS=OFF \
  -DPLOD_BUILD_EXAMPLES=OFF -DPLOD_WARNINGS_AS_ERRORS=ON
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:allocator_may_return_null=1 \
UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build-asan --output-on-failure -j2 \
    -E '^(FuzzOctreeBuild\.Short|FuzzOctreeFile\.Short|External\.InstalledPackage)$'
