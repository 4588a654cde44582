#!/usr/bin/env bash
# levelfuse quick start on Debian bookworm: install what is needed, build, run.
#
#   tools/quickstart.sh demo    reconstruct a noisy synthetic torus (and the bunny) into out/
#   tools/quickstart.sh test    build everything and run the whole test suite
#   tools/quickstart.sh bench   also install ITK and run the benchmarks (JSON in out/)
#
# Run as root, or as a user who may sudo. Build directory: $LEVELFUSE_BUILD_DIR
# (default build/), sanitizer builds with LEVELFUSE_SANITIZER=address|thread;
# tests of a label left out with LEVELFUSE_SKIP_LABEL (e.g. paper), tests
# whose names match a regular expression with LEVELFUSE_SKIP_TESTS.
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
mode=${1:-demo}
build=${LEVELFUSE_BUILD_DIR:-$root/build}
sanitizer=${LEVELFUSE_SANITIZER:-}
jobs=${LEVELFUSE_JOBS:-2}

case "$mode" in demo|test|bench) ;; *) echo "usage: $0 demo|test|bench" >&2; exit 2 ;; esac

# The demo installs what it builds and runs: the converter and the Python module.
packages=(cmake g++ ninja-build ccache pkg-config
          libopenvdb-dev libopenvdb-tools libtbb-dev libzstd-dev libboost-iostreams-dev
          libcli11-dev nlohmann-json3-dev libpng-dev libpugixml-dev libopenexr-dev
          pybind11-dev python3-dev python3-numpy python3-openvdb libboost-python-dev)
[ "$mode" != demo ] && packages+=(libgtest-dev libbenchmark-dev python3-pytest libopenmpi-dev openmpi-bin)
[ "$mode" = bench ] && packages+=(libinsighttoolkit5-dev libopen3d-dev python3-open3d time)

"$root/tools/install-packages.sh" "${packages[@]}"

# The demo builds neither the tests nor the benchmarks; benchmarks say nothing
# under a sanitizer, so sanitizer builds leave them out.
options=(-DCMAKE_BUILD_TYPE=Release -DLEVELFUSE_SANITIZER="$sanitizer")
benchmarks=ON
[ -n "$sanitizer" ] && benchmarks=OFF
case "$mode" in
  demo) options+=(-DLEVELFUSE_BUILD_TESTS=OFF -DLEVELFUSE_BUILD_BENCHMARKS=OFF) ;;
  test) options+=(-DLEVELFUSE_BUILD_TESTS=ON -DLEVELFUSE_BUILD_BENCHMARKS="$benchmarks") ;;
  bench) options+=(-DLEVELFUSE_BUILD_BENCHMARKS=ON) ;;
esac
"$root/tools/configure.sh" "$build" "${options[@]}"

mkdir -p "$root/out"
case "$mode" in
  demo)
    # The converter first, and the torus and the bunny from it; the Python module after them.
    cmake --build "$build" -j "$jobs" --target levelfuse_cli
    levelfuse="$build/tools/levelfuse/levelfuse"
    echo "== six range scans of a torus with noise of 20% of its tube's diameter (the paper's Fig. 10)"
    "$levelfuse" synth --shape torus --noise 0.2 -o "$root/out/torus-scans"
    echo "== reconstructing it"
    "$levelfuse" reconstruct "$root/out/torus-scans/scans.json" -o "$root/out/torus.vdb" \
      --mesh "$root/out/torus.ply" --preview "$root/out/torus.png"
    vdb_print "$root/out/torus.vdb"
    bunny="$root/../shared/data/stanford/bunny/bun.conf"
    if [ -f "$bunny" ]; then
      echo "== reconstructing the Stanford bunny from its ten scans"
      "$levelfuse" reconstruct "$bunny" -o "$root/out/bunny.vdb" --mesh "$root/out/bunny.ply" \
        --preview "$root/out/bunny.png"
    fi
    frames="$root/../shared/data/7scenes"
    if [ -d "$frames" ]; then
      cmake --build "$build" -j "$jobs" --target levelfuse_python
      echo "== from Python: 50 depth frames of a room fused one at a time (examples/fuse_depth_frames.py)"
      PYTHONPATH="$build/python" /usr/bin/python3 "$root/examples/fuse_depth_frames.py" "$frames" "$root/out"
    fi
    echo "== the Python module: cmake --build $build --target levelfuse_python, then"
    echo "   PYTHONPATH=$build/python python3 and import levelfuse (or cmake --install $build)"
    ;;
  test)
    cmake --build "$build" -j "$jobs"
    echo "== running the tests"
    skip=()
    [ -n "${LEVELFUSE_SKIP_LABEL:-}" ] && skip+=(-LE "$LEVELFUSE_SKIP_LABEL")
    [ -n "${LEVELFUSE_SKIP_TESTS:-}" ] && skip+=(-E "$LEVELFUSE_SKIP_TESTS")
    (cd "$build" && ctest --output-on-failure -j "$jobs" "${skip[@]}")
    ;;
  bench)
    cmake --build "$build" -j "$jobs" --target levelset_benchmarks scan_benchmarks recon_benchmarks depth_benchmarks \
      scene_benchmarks station_benchmarks python_benchmarks mpi_benchmarks heldout_ruler levelfuse_cli
    echo "== running the benchmarks (this takes a while)"
    ITK_GLOBAL_DEFAULT_THREADER=Platform "$build/benchmarks/levelset_benchmarks" \
      --benchmark_format=json --benchmark_out="$root/out/levelset_benchmarks.json" --benchmark_out_format=json
    # The reconstruction shared by MPI ranks: one job per benchmark and rank count, each rank's peak its own.
    for name in $("$build/benchmarks/mpi_benchmarks" --benchmark_list_tests); do
      for ranks in 1 2 4; do
        OMPI_MCA_btl_vader_single_copy_mechanism=none mpirun --oversubscribe --allow-run-as-root -np "$ranks" \
          "$build/benchmarks/mpi_benchmarks" --benchmark_filter="^$name\$" --benchmark_format=json \
          --benchmark_out="$root/out/mpi_benchmarks-${name//\//_}-np$ranks.json" --benchmark_out_format=json
      done
    done
    # One process per benchmark, so that each reports its own peak memory. Every peer runs
    # in the environment it is given, as its users run it: nothing is set for or against it.
    for program in scan_benchmarks recon_benchmarks depth_benchmarks scene_benchmarks station_benchmarks \
                   python_benchmarks; do
      for name in $("$build/benchmarks/$program" --benchmark_list_tests); do
        "$build/benchmarks/$program" --benchmark_filter="^$name\$" --benchmark_format=json \
          --benchmark_out="$root/out/$program-${name//\//_}.json" --benchmark_out_format=json
      done
    done
    # Depth video as whole processes: the converter against Open3D's Python API, in turn.
    if [ -d "$root/../shared/data/7scenes-seq" ]; then
      /usr/bin/python3 "$root/benchmarks/depth_video_processes.py" --build "$build" --out "$root/out/depth-video" \
        --json "$root/out/depth_video_processes.json" | tee "$root/out/depth_video_processes.md"
    fi
    ;;
esac
