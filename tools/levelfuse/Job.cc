// levelfuse CLI: joining and leaving the MPI job.

#include "Job.h"

#include <cstdlib>
#include <stdexcept>
#include <string>

#if defined(LEVELFUSE_HAVE_MPI)
#include <levelfuse/mpi/RankTeam.h>

#include <mpi.h>
#endif

namespace levelfuse::cli {

namespace {

/// True if a launcher that runs MPI jobs started this process.
bool launchedByMpirun() {
  for (const char* variable : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (std::getenv(variable)) return true;
  return false;
}

#if defined(LEVELFUSE_HAVE_MPI)
std::unique_ptr<mpi::RankTeam> gTeam;
#endif

}  // namespace

void joinJobIfLaunched(int& argc, char**& argv) {
  if (!launchedByMpirun()) return;
#if defined(LEVELFUSE_HAVE_MPI)
  MPI_Init(&argc, &argv);
  gTeam = std::make_unique<mpi::RankTeam>(MPI_COMM_WORLD);
#else
  (void)argc;
  (void)argv;
  throw std::runtime_error("mpirun started this levelfuse, which was built without MPI: install libopenmpi-dev "
                           "and build again (LEVELFUSE_MPI), or run it without mpirun");
#endif
}

void leaveJob() {
#if defined(LEVELFUSE_HAVE_MPI)
  if (!gTeam) return;
  gTeam.reset();
  MPI_Finalize();
#endif
}

const SlabTeam* jobTeam() {
#if defined(LEVELFUSE_HAVE_MPI)
  if (gTeam && gTeam->size() > 1) return gTeam.get();
#endif
  return nullptr;
}

bool leadsTheJob() { return jobRank() == 0; }

void abortJobIfShared(int exitCode) {
#if defined(LEVELFUSE_HAVE_MPI)
  if (jobTeam()) MPI_Abort(MPI_COMM_WORLD, exitCode);
#else
  (void)exitCode;
#endif
}

std::uint64_t totalOverJob(std::uint64_t count) {
  const SlabTeam* team = jobTeam();
  return team ? team->total(count) : count;
}

std::vector<std::string> everyRanksText(const std::string& text) {
  const SlabTeam* team = jobTeam();
  if (!team) return {text};
  const PackedLeaves bytes(text.begin(), text.end());
  std::vector<std::string> all;
  for (const PackedLeaves& received : team->exchange(std::vector<PackedLeaves>(static_cast<std::size_t>(team->size()), bytes)))
    all.emplace_back(received.begin(), received.end());
  return all;
}

int jobRank() {
  const SlabTeam* team = jobTeam();
  return team ? team->rank() : 0;
}

int jobRanks() {
  const SlabTeam* team = jobTeam();
  return team ? team->size() : 1;
}

std::uint64_t ghostBytesSent() {
#if defined(LEVELFUSE_HAVE_MPI)
  if (gTeam) return gTeam->ghostBytesSent();
#endif
  return 0;
}

std::vector<ProcessFacts> gatherRankFacts(const ProcessFacts& facts) {
#if defined(LEVELFUSE_HAVE_MPI)
  if (const SlabTeam* team = jobTeam()) {
    std::vector<ProcessFacts> all(team->rank() == 0 ? static_cast<std::size_t>(team->size()) : 0);
    MPI_Gather(&facts, sizeof(ProcessFacts), MPI_BYTE, all.data(), sizeof(ProcessFacts), MPI_BYTE, 0, MPI_COMM_WORLD);
    return all;
  }
#endif
  return {facts};
}

}  // namespace levelfuse::cli
