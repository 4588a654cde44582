#!/usr/bin/env bash
# levelfuse quick start on Debian bookworm: install what is needed, build, run.
#
#   tools/quickstart.sh demo    evolve a generated dumbbell into out/dumbbell.vdb
#   tools/quickstart.sh test    build everything and run the whole test suite
#   tools/quickstart.sh bench   also install ITK and run the benchmarks (JSON in out/)
#
# Run as root, or as a user who may sudo. Build directory: $LEVELFUSE_BUILD_DIR
# (default build/), sanitizer builds with LEVELFUSE_SANITIZER=address|thread.
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
mode=${1:-demo}
build=${LEVELFUSE_BUILD_DIR:-$root/build}
sanitizer=${LEVELFUSE_SANITIZER:-}
jobs=${LEVELFUSE_JOBS:-2}

case "$mode" in demo|test|bench) ;; *) echo "usage: $0 demo|test|bench" >&2; exit 2 ;; esac

packages=(cmake g++ make ccache pkg-config
          libopenvdb-dev libopenvdb-tools libtbb-dev libblosc-dev libboost-iostreams-dev
          libgtest-dev libbenchmark-dev libcli11-dev nlohmann-json3-dev libpng-dev libopenexr-dev)
[ "$mode" = bench ] && packages+=(libinsighttoolkit5-dev)

"$root/tools/install-packages.sh" "${packages[@]}"

# Benchmarks say nothing under a sanitizer: sanitizer builds leave them out.
options=(-DCMAKE_BUILD_TYPE=Release -DLEVELFUSE_SANITIZER="$sanitizer")
[ -n "$sanitizer" ] && options+=(-DLEVELFUSE_BUILD_BENCHMARKS=OFF)
echo "== configuring $build"
cmake -S "$root" -B "$build" "${options[@]}" >/dev/null

mkdir -p "$root/out"
case "$mode" in
  demo)
    cmake --build "$build" -j "$jobs" --target levelfuse_cli
    echo "== evolving a dumbbell under mean-curvature flow"
    "$build/tools/levelfuse/levelfuse" evolve --shape dumbbell -o "$root/out/dumbbell.vdb"
    vdb_print "$root/out/dumbbell.vdb"
    ;;
  test)
    cmake --build "$build" -j "$jobs"
    echo "== running the tests"
    (cd "$build" && ctest --output-on-failure -j "$jobs")
    ;;
  bench)
    cmake --build "$build" -j "$jobs" --target levelset_benchmarks
    echo "== running the benchmarks (this takes a while)"
    ITK_GLOBAL_DEFAULT_THREADER=Platform "$build/benchmarks/levelset_benchmarks" \
      --benchmark_format=json --benchmark_out="$root/out/levelset_benchmarks.json" --benchmark_out_format=json
    ;;
esac
