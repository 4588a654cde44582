// A real terrestrial station, held out column by column: the pump room of
// ../shared/data/e57/pumpA.e57 (one station, 345 columns x 1074 rows,
// 155,201 returns). The surface is made from its even columns, with the
// default options, and measured on the returns of its odd columns, which no
// method saw: the accuracy of a surface between a scanner's rays, without a
// ground truth.
//
//   BM_StationHeldOut/levelfuse   Reconstructor's defaults (a station is a
//                                 scene: one grid, no prior), the mesh
//                                 trimmed of what no scan saw, as the
//                                 converter writes it
//   BM_StationHeldOut/poisson     screened Poisson (Open3D 0.16, depth 9),
//                                 normals from 12 neighbours turned toward
//                                 the scanner, from the same points
//
// Each reports real time per surface (reading the E57 file included) and
//   held_out_points           the odd columns' returns
//   mean_mm, median_mm,       their exact distances to the mesh
//   p90_mm
//   within_1cm, within_2cm    the shares of them within 1 and 2 cm
//   peak_rss_mb               the process's peak resident memory while it ran
//   triangles
// Run with --benchmark_format=json; see docs/BENCHMARKS.md.

#include "BenchmarkSupport.h"

#include <levelfuse/geometry/NearestTriangle.h>
#include <levelfuse/io/scans/E57Scans.h>
#include <levelfuse/levelset/Mesh.h>
#include <levelfuse/recon/DataFit.h>
#include <levelfuse/recon/Reconstructor.h>
#include <levelfuse/recon/ScansReconstruction.h>

#if defined(LEVELFUSE_HAVE_OPEN3D)
#include "peers/PoissonRecon.h"
#endif

#include <tbb/global_control.h>

#include <benchmark/benchmark.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

namespace levelfuse::bench {
namespace {

using openvdb::Vec3d;

const std::string kPumpRoom = std::string(LEVELFUSE_SHARED_DATA_DIR) + "/e57/pumpA.e57";

/// The station's columns of one parity (0: even, 1: odd), a grid of its own.
io::StationGrid columnsOf(const io::StationGrid& station, int parity) {
  io::StationGrid half;
  half.rows = station.rows;
  half.scannerToWorld = station.scannerToWorld;
  const bool coloured = !station.colours.empty();
  for (int c = parity; c < station.columns; c += 2) {
    ++half.columns;
    for (int r = 0; r < station.rows; ++r) {
      const std::size_t i = static_cast<std::size_t>(c) * static_cast<std::size_t>(station.rows) + r;
      half.points.push_back(station.points[i]);
      half.intensities.push_back(station.intensities[i]);
      if (coloured) half.colours.push_back(station.colours[i]);
      half.returns += station.points[i] != Vec3d(0.0);
    }
  }
  return half;
}

io::StationGrid pumpRoom() {
  io::StationGrid station;
  io::readE57Scans(kPumpRoom, [&](io::E57Scan&& scan) { station = std::move(scan.station); });
  return station;
}

/// The returns of a grid in the world.
std::vector<Vec3d> returnsOf(const io::StationGrid& grid) {
  std::vector<Vec3d> world;
  for (const Vec3d& p : grid.points)
    if (p != Vec3d(0.0)) world.push_back(grid.scannerToWorld.transform(p));
  return world;
}

void reportHeldOut(benchmark::State& state, const TriangleMesh& mesh, const std::vector<Vec3d>& heldOut) {
  const NearestTriangle nearest(mesh.xyz, mesh.triangles);
  std::vector<double> distances(heldOut.size());
  for (std::size_t i = 0; i < heldOut.size(); ++i) distances[i] = nearest.distance(heldOut[i]);
  const auto share = [&](double within) {
    return static_cast<double>(std::count_if(distances.begin(), distances.end(),
                                             [&](double d) { return d <= within; })) /
           static_cast<double>(distances.size());
  };
  state.counters["within_1cm"] = share(0.01);
  state.counters["within_2cm"] = share(0.02);
  const DataFit fit = summariseDistances(std::move(distances));
  state.counters["held_out_points"] = static_cast<double>(heldOut.size());
  state.counters["mean_mm"] = 1000.0 * fit.mean;
  state.counters["median_mm"] = 1000.0 * fit.median;
  state.counters["p90_mm"] = 1000.0 * fit.p90;
  state.counters["triangles"] = static_cast<double>(mesh.triangleCount());
}

TriangleMesh levelfuseSurface(const io::StationGrid& even) {
  std::vector<RangeMap> maps;
  maps.push_back(io::rangeMapFromStationGrid(even, io::ScanLoadOptions().stationSigma, kPumpRoom,
                                             "the even columns", "pumpA even columns"));
  const Reconstructor reconstructor(std::move(maps));
  const ReconstructionResult result = reconstructor.run();
  const bool trim = trimsUnseen(reconstructor.summary().aScene());
  return meshShown(*result.levelSet, trim ? result.weight.get() : nullptr, 0.0, nullptr);
}

void heldOutLevelfuse(benchmark::State& state) {
  if (!std::filesystem::exists(kPumpRoom)) {
    state.SkipWithError("../shared/data/e57 is absent");
    return;
  }
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
  TriangleMesh mesh;
  resetPeakResident();
  for (auto _ : state) mesh = levelfuseSurface(columnsOf(pumpRoom(), 0));
  state.counters["peak_rss_mb"] = peakResidentMegabytes();
  reportHeldOut(state, mesh, returnsOf(columnsOf(pumpRoom(), 1)));
}

#if defined(LEVELFUSE_HAVE_OPEN3D)
TriangleMesh poissonSurface(const io::StationGrid& even) {
  peers::PoissonScan scan;
  for (const Vec3d& p : even.points)
    if (p != Vec3d(0.0)) scan.points.push_back({p.x(), p.y(), p.z()});
  scan.scannerPosition = std::array<double, 3>{0.0, 0.0, 0.0};
  for (int i = 0; i < 16; ++i) scan.scanToWorld[i] = even.scannerToWorld(i / 4, i % 4);
  return toTriangleMesh(peers::poissonReconstruct({scan}, 9, 2));
}

void heldOutPoisson(benchmark::State& state) {
  if (!std::filesystem::exists(kPumpRoom)) {
    state.SkipWithError("../shared/data/e57 is absent");
    return;
  }
  TriangleMesh mesh;
  resetPeakResident();
  for (auto _ : state) mesh = poissonSurface(columnsOf(pumpRoom(), 0));
  state.counters["peak_rss_mb"] = peakResidentMegabytes();
  reportHeldOut(state, mesh, returnsOf(columnsOf(pumpRoom(), 1)));
}
#endif

void registerAll() {
  benchmark::RegisterBenchmark("BM_StationHeldOut/levelfuse", heldOutLevelfuse)
      ->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();
#if defined(LEVELFUSE_HAVE_OPEN3D)
  benchmark::RegisterBenchmark("BM_StationHeldOut/poisson", heldOutPoisson)
      ->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();
#endif
}

}  // namespace
}  // namespace levelfuse::bench

int main(int argc, char** argv) { return levelfuse::bench::runBenchmarks(argc, argv, levelfuse::bench::registerAll); }
