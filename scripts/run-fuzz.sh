#!/usr/bin/env bash
# Builds a libFuzzer target of the VTK-free kernels with clang-14 and fuzzes for a while.
#   bash scripts/run-fuzz.sh [seconds]      (default 60)
# PLOD_FUZZ_TARGET=FuzzOctreeFile fuzzes the octree-file reader instead of the build
# (FuzzOctreeBuild, the default), from Testing/Fuzz/corpus-file.
# Installs nothing (scripts/install-deps.sh provides clang-14 and libclang-rt-14-dev).
# Configures and builds build-fuzz/ (or $PLOD_FUZZ_BUILD_DIR), fuzzes a copy of
# Testing/Fuzz/corpus (the repository is not modified), prints libFuzzer's figures, and exits
# non-zero on a crash, a failed check, a leak or a timeout. Crash inputs are kept in
# <build>/artifacts/. Extra libFuzzer options: PLOD_FUZZ_OPTIONS="-seed=1 ..."; the time after
# which one input counts as a hang: PLOD_FUZZ_TIMEOUT (seconds, default 25).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
build="${PLOD_FUZZ_BUILD_DIR:-build-fuzz}"
target="${PLOD_FUZZ_TARGET:-FuzzOctreeBuild}"
case "$target" in
  FuzzOctreeBuild) seeds=Testing/Fuzz/corpus ;;
  FuzzOctreeFile) seeds=Testing/Fuzz/corpus-file ;;
  FuzzPLYPieces) seeds=Testing/Fuzz/corpus-ply ;;
  *) echo "run-fuzz.sh: unknown PLOD_FUZZ_TARGET '$target'" >&2; exit 2 ;;
esac
for tool in clang-14 clang++-14 cmake ninja; do
  command -v "$tool" > /dev/null || { echo "run-fuzz.sh: $tool not found (run scripts/install-deps.sh)" >&2; exit 2; }
done
if [ ! -f "$build/CMakeCache.txt" ]; then
  mkdir -p "$build"
  CC=clang-14 CXX=clang++-14 cmake -S . -B "$build" -G Ninja -DPLOD_BUILD_FUZZERS=ON \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo > "$build/configure.log" 2>&1 \
    || { cat "$build/configure.log" >&2; rm -f "$build/CMakeCache.txt"; exit 2; }
fi
cmake --build "$build" --target "$target"
work="$build/fuzz-run-$target"
rm -rf "$work"
mkdir -p "$work/corpus" "$build/artifacts"
cp "$seeds"/* "$work/corpus/"
echo "run-fuzz.sh: fuzzing $target for $seconds s on a copy of $seeds ($(ls "$work/corpus" | wc -l) files)"
# -timeout: a hang is an input that takes longer (typical inputs take tens of milliseconds).
# -max_len: a few thousand points in the compact encodings; longer models come from the
# generator inside the target. -rss_limit_mb: the largest builds stay far below it.
set +e
"$build/bin/$target" "$work/corpus" \
  "-max_total_time=$seconds" "-timeout=${PLOD_FUZZ_TIMEOUT:-25}" -max_len=16384 -rss_limit_mb=2048 \
  -print_final_stats=1 -artifact_prefix="$build/artifacts/" ${PLOD_FUZZ_OPTIONS:-} \
  2>&1 | tee "$work/fuzz.log" | grep --line-buffered -v '^#[0-9]*[[:space:]]*\(NEW\|REDUCE\)'
status="${PIPESTATUS[0]}"
set -e
echo "run-fuzz.sh: corpus after the run: $(ls "$work/corpus" | wc -l) files in $work/corpus"
if [ "$status" -ne 0 ]; then
  echo "run-fuzz.sh: the fuzzer failed (exit $status); see $work/fuzz.log and $build/artifacts/" >&2
  exit 1
fi
echo "run-fuzz.sh: clean"
