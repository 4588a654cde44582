// Helpers shared by levelfuse's benchmarks.
#pragma once

#include "peers/PeerMesh.h"

#include <levelfuse/core/PhaseClock.h>
#include <levelfuse/levelset/Mesh.h>

#include <openvdb/openvdb.h>

#include <cstddef>
#include <utility>

namespace levelfuse::bench {

/// Number of threads for a benchmark run: the second benchmark argument.
/// Thread counts are set with tbb::global_control (and ITK's threader).
constexpr int kDefaultThreads = 2;

/// Mean distance of a grid's zero crossings from `centre` (world units).
double meanRadius(const openvdb::FloatGrid& grid, const openvdb::Vec3d& centre);

/// Simulated time per iteration, normalised so that R(t)^2 = R0^2 - 4t (the
/// sum of principal curvatures with weight 1), measured from the shape.
inline double simulatedTimePerIteration(double r0, double r1, std::size_t iterations) {
  return (r0 * r0 - r1 * r1) / (4.0 * static_cast<double>(iterations));
}

/// The process's peak resident memory since the last resetPeakResident() (or
/// since it started), in MB.
double peakResidentMegabytes();
/// Starts a new peak (Linux's /proc/self/clear_refs): what one benchmark
/// measured afterwards does not count toward the next one's peak. Without it
/// (another system), one benchmark per process reports its own peak.
void resetPeakResident();

/// CPU time the process has used so far (levelfuse::processCpuSeconds): what a
/// run costs when the machine is shared and its real time is not its own.
using levelfuse::processCpuSeconds;

/// Iterations timed per repetition for a sphere of radius R: enough to measure,
/// few enough that the sphere changes little.
std::size_t iterationsFor(int radius);

/// The main function of a benchmark program: OpenVDB initialised, the
/// benchmarks registered by `registerAll`, Google Benchmark run on the command line.
int runBenchmarks(int argc, char** argv, void (*registerAll)());

/// A peer's mesh as levelfuse's, to be measured with levelfuse's rulers.
inline TriangleMesh toTriangleMesh(peers::PeerMesh mesh) {
  TriangleMesh out;
  out.xyz = std::move(mesh.xyz);
  out.triangles = std::move(mesh.triangles);
  return out;
}

}  // namespace levelfuse::bench
