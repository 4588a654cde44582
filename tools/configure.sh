#!/usr/bin/env bash
# Configures a levelfuse build folder for the scripts beside it: a new folder
# for Ninja; one configured before keeps its generator, which CMake cannot change.
#
#   tools/configure.sh BUILD_DIR [CMAKE_OPTION...]
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=$1
shift
generator=()
[ -f "$build/CMakeCache.txt" ] || generator=(-G Ninja)
echo "== configuring $build"
cmake -S "$root" -B "$build" "${generator[@]}" "$@" >/dev/null
