#!/usr/bin/env bash
# Builds levelfuse's libFuzzer targets (clang, ASan + UBSan) and runs each for
# a while, as many at a time as $LEVELFUSE_JOBS (default 2); fails if any of
# them finds a crash, a leak, a hang or an input that needs too much memory.
#
#   tools/fuzz.sh [seconds]      seconds per target (default 60)
#
# Build directory: $LEVELFUSE_FUZZ_BUILD_DIR (default build-fuzz/). Targets to
# run: $LEVELFUSE_FUZZERS (default: all). The inputs each run adds to its corpus
# are kept in <build>/corpus/<target>/ and found again by the next run; what a
# fuzzer finds lands in <build>/findings/<target>/. See docs/RELIABILITY.md.
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
seconds=${1:-60}
build=${LEVELFUSE_FUZZ_BUILD_DIR:-$root/build-fuzz}
jobs=${LEVELFUSE_JOBS:-2}
fuzzers=${LEVELFUSE_FUZZERS:-FuzzPly FuzzStanfordConf FuzzManifest FuzzDepthPng FuzzDepthPfm FuzzDepthExr FuzzCameraText FuzzTumText FuzzPtx FuzzE57 FuzzPoints FuzzVdb}

packages=(cmake clang libclang-rt-14-dev ninja-build ccache pkg-config
          libopenvdb-dev libtbb-dev libzstd-dev libboost-iostreams-dev nlohmann-json3-dev libpng-dev libpugixml-dev)
"$root/tools/install-packages.sh" "${packages[@]}"

CC=clang CXX=clang++ "$root/tools/configure.sh" "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLEVELFUSE_BUILD_FUZZERS=ON \
  -DLEVELFUSE_BUILD_TESTS=OFF -DLEVELFUSE_BUILD_BENCHMARKS=OFF -DLEVELFUSE_BUILD_TOOLS=OFF -DLEVELFUSE_PYTHON=OFF
cmake --build "$build" -j "$jobs" --target fuzzers

# The targets write each input to a file; a crashed run leaves its folder here.
export TMPDIR="$build/tmp"
mkdir -p "$TMPDIR"
# run_fuzzer <target>: runs it for $seconds; its output goes to <build>/<target>.log
# and its exit code to <build>/<target>.status.
run_fuzzer() {
  local fuzzer=$1
  rm -f "$build/$fuzzer.status"
  local corpus="$build/corpus/$fuzzer" findings="$build/findings/$fuzzer"
  mkdir -p "$corpus" "$findings"
  local dict=()
  [ -f "$root/tests/fuzz/$fuzzer.dict" ] && dict=(-dict="$root/tests/fuzz/$fuzzer.dict")
  # Inputs up to 4 KiB, but .vdb files up to 32 KiB (one internal node's masks alone take 8 KiB)
  # and E57 files up to 16 KiB (a file is whole pages of 1 KiB, its XML section the last).
  local max_len=4096
  [ "$fuzzer" = FuzzVdb ] && max_len=32768
  [ "$fuzzer" = FuzzE57 ] && max_len=16384
  # New inputs go to the first folder; the committed seeds are only read.
  local status=0
  "$build/tests/fuzz/$fuzzer" "$corpus" "$root/tests/fuzz/corpus/$fuzzer" "${dict[@]}" \
    -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=$max_len \
    -artifact_prefix="$findings/" -print_final_stats=1 >"$build/$fuzzer.log" 2>&1 || status=$?
  echo "$status" >"$build/$fuzzer.status"
}

# Each target runs on one core: $jobs of them at a time.
echo "== running each target for ${seconds}s, $jobs at a time"
running=0
for fuzzer in $fuzzers; do
  if [ "$running" -ge "$jobs" ]; then
    wait -n
    running=$((running - 1))
  fi
  run_fuzzer "$fuzzer" &
  running=$((running + 1))
done
wait

failed=()
for fuzzer in $fuzzers; do
  echo "== $fuzzer for ${seconds}s"
  if [ "$(cat "$build/$fuzzer.status")" = 0 ]; then
    grep -E '^(stat::number_of_executed_units|stat::peak_rss_mb)' "$build/$fuzzer.log" | tr '\n' ' '
    echo
  else
    echo "!! $fuzzer failed; its log ends:"
    tail -n 40 "$build/$fuzzer.log"
    echo "!! reproduce with: $build/tests/fuzz/$fuzzer $(ls -t "$build/findings/$fuzzer"/* 2>/dev/null | head -n 1)"
    failed+=("$fuzzer")
  fi
done

if [ ${#failed[@]} -gt 0 ]; then
  echo "== fuzzing found problems in: ${failed[*]}"
  exit 1
fi
echo "== fuzzing found nothing in ${seconds}s per target"
