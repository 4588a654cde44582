// The reconstruction shared by the ranks of an MPI job (mpi/RankTeam.h), one
// slab of every grid each: the Stanford bunny at 0.25 and 0.125 mm and the
// dragon at 0.25 and 0.125 mm, from their scans; and the bunny at 0.125 mm and
// the dragon at both sizes with each rank keeping its piece of the output
// (BM_*InPiecesOnRanks, ReconstructionOptions::keepPieces), where rank 0
// assembles nothing. Run it as one MPI job per rank count,
//   mpirun -np N mpi_benchmarks --benchmark_format=json
// with N = 1, 2, 4 (tools/quickstart.sh bench does): a process's peak
// resident memory is its own, so each count is its own run, and the ratios
// between runs are the result (docs/BENCHMARKS.md, "Many processes").
//
// Every rank runs every benchmark with one iteration (ranks meet in
// collectives, so none may stop timing early); rank 0 reports, with the real
// time per reconstruction (loading included):
//   ranks                   N
//   peak_rss_mb_rank0       rank 0's peak resident memory: its slab, then the
//                           whole level set and its weight grid (in pieces: its
//                           piece of them)
//   peak_rss_mb_others      the largest of the other ranks' peaks
//   leaves_max_over_mean    the finest grid's leaf nodes of the most loaded rank
//                           over the ranks' mean (1 is an even split)
//   ghost_mb_per_iteration  ghosts sent per iteration by the rank that sends most
//   active                  voxels of the final active set (the same for any N)

#include "BenchmarkSupport.h"

#include <levelfuse/io/scans/StanfordScans.h>
#include <levelfuse/mpi/RankTeam.h>
#include <levelfuse/recon/Reconstructor.h>

#include <benchmark/benchmark.h>
#include <mpi.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <initializer_list>
#include <string>
#include <vector>

namespace levelfuse::bench {
namespace {

const std::string kData = LEVELFUSE_SHARED_DATA_DIR;

struct Scans {
  std::string conf;
  openvdb::Vec3d towardScanner;
};

const Scans kBunny{kData + "/stanford/bunny/bun.conf", openvdb::Vec3d(0.0, 0.0, 1.0)};
/// The dragon's scanner looked along this direction (the converter's example).
const Scans kDragon{kData + "/stanford/dragon/dragonStandRight.conf", openvdb::Vec3d(0.46, 0.04, 0.89)};

/// Every rank's `value`, at rank 0.
std::vector<double> atRankZero(double value, const mpi::RankTeam& team) {
  std::vector<double> all(static_cast<std::size_t>(team.size()));
  MPI_Gather(&value, 1, MPI_DOUBLE, all.data(), 1, MPI_DOUBLE, 0, team.communicator());
  return all;
}

void reconstructOnRanks(benchmark::State& state, const Scans& scans, bool inPieces) {
  if (!std::filesystem::exists(scans.conf)) {
    state.SkipWithError((scans.conf + " is absent").c_str());
    return;
  }
  const mpi::RankTeam team;
  const double voxelSize = static_cast<double>(state.range(0)) * 1e-6;
  ReconstructionResult result;
  resetPeakResident();
  for (auto _ : state) {
    result = ReconstructionResult();
    io::StanfordScanOptions load;
    load.towardScanner = scans.towardScanner;
    ReconstructionOptions options;
    options.voxelSize = voxelSize;
    options.keepPieces = inPieces;
    result = Reconstructor(io::loadStanfordScans(scans.conf, load), options).run({}, {}, &team);
  }
  int iterations = 0;
  for (const LevelReport& level : result.levels) iterations += level.iterations;
  const std::vector<double> peaks = atRankZero(peakResidentMegabytes(), team);
  const std::vector<double> leaves = atRankZero(static_cast<double>(result.levels.back().ownLeafNodes), team);
  const std::vector<double> ghosts =
      atRankZero(static_cast<double>(team.ghostBytesSent()) / 1048576.0 / std::max(iterations, 1), team);
  if (team.rank() != 0) return;
  double mean = 0.0;
  for (const double l : leaves) mean += l / static_cast<double>(leaves.size());
  state.counters["ranks"] = team.size();
  state.counters["peak_rss_mb_rank0"] = peaks.front();
  state.counters["peak_rss_mb_others"] = peaks.size() > 1 ? *std::max_element(peaks.begin() + 1, peaks.end()) : 0.0;
  state.counters["leaves_max_over_mean"] = *std::max_element(leaves.begin(), leaves.end()) / mean;
  state.counters["ghost_mb_per_iteration"] = *std::max_element(ghosts.begin(), ghosts.end());
  state.counters["active"] = static_cast<double>(result.levels.back().activeSetVoxels);
}

/// Registers `name`: the reconstruction of `scans` on the job's ranks at each
/// voxel size (micrometres), whole or in pieces; one iteration each.
void registerOnRanks(const char* name, const Scans& scans, bool inPieces, std::initializer_list<int> voxelMicrometres) {
  benchmark::internal::Benchmark* b = benchmark::RegisterBenchmark(
      name, [&scans, inPieces](benchmark::State& s) { reconstructOnRanks(s, scans, inPieces); });
  for (const int size : voxelMicrometres) b->Arg(size);
  b->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();
}

void registerAll() {
  registerOnRanks("BM_BunnyOnRanks", kBunny, false, {250, 125});
  registerOnRanks("BM_BunnyInPiecesOnRanks", kBunny, true, {125});
  registerOnRanks("BM_DragonOnRanks", kDragon, false, {250, 125});
  registerOnRanks("BM_DragonInPiecesOnRanks", kDragon, true, {250, 125});
}

/// Prints nothing: the ranks other than rank 0 run the benchmarks silently.
class SilentReporter : public benchmark::BenchmarkReporter {
 public:
  bool ReportContext(const Context&) override { return true; }
  void ReportRuns(const std::vector<Run>&) override {}
};

}  // namespace
}  // namespace levelfuse::bench

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  openvdb::initialize();
  levelfuse::bench::registerAll();
  // Only rank 0 writes the results: the others drop --benchmark_out.
  std::vector<char*> args(argv, argv + argc);
  if (rank != 0)
    args.erase(std::remove_if(args.begin() + 1, args.end(),
                              [](const char* a) { return std::strncmp(a, "--benchmark_out", 15) == 0; }),
               args.end());
  int count = static_cast<int>(args.size());
  benchmark::Initialize(&count, args.data());
  levelfuse::bench::SilentReporter silent;
  if (rank == 0) benchmark::RunSpecifiedBenchmarks();
  else benchmark::RunSpecifiedBenchmarks(&silent);
  benchmark::Shutdown();
  MPI_Finalize();
  return 0;
}
