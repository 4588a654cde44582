// levelfuse CLI: the MPI job a process runs in, when mpirun started it.
//
// `mpirun -np N levelfuse reconstruct ...` runs N copies of the converter:
// each reads the scans and evolves one slab of every grid (recon/
// Reconstructor.h, run with a team); the first rank writes the outputs and
// prints. A rank that fails ends the whole job (MPI_Abort) after its one-line
// error, so no rank waits for it and nothing is written.
#pragma once

#include <levelfuse/levelset/SlabTeam.h>
#include <levelfuse/recon/RunSummary.h>

#include <cstdint>
#include <string>
#include <vector>

namespace levelfuse::cli {

/// Joins the MPI job if mpirun (OpenMPI or a PMI launcher) started this
/// process; call once, first thing in main. Throws std::runtime_error if it
/// did and this converter was built without MPI.
void joinJobIfLaunched(int& argc, char**& argv);
/// Leaves the job (MPI_Finalize), if joined; at the end of main.
void leaveJob();
/// The job's ranks as a team sharing an evolution, or null outside a job of
/// more than one rank.
const SlabTeam* jobTeam();
/// True unless this process is a rank other than the first: it prints and writes.
bool leadsTheJob();
/// Ends every rank of the job with `exitCode` when this one failed; returns
/// outside a job of more than one rank.
void abortJobIfShared(int exitCode);

/// The sum of every rank's `count`, on every rank; `count` itself outside a
/// job of more than one rank. Every rank of a job must call it.
std::uint64_t totalOverJob(std::uint64_t count);
/// Every rank's `text`, in rank order, on every rank; {text} outside a job.
/// Every rank of a job must call it.
std::vector<std::string> everyRanksText(const std::string& text);
/// This rank's number and the job's ranks: 0 and 1 outside a job.
int jobRank();
int jobRanks();

/// The bytes of ghosts this rank has sent its neighbours so far (0 outside a job).
std::uint64_t ghostBytesSent();
/// Every rank's facts, in rank order, at the first rank (empty on the
/// others); outside a job, `facts` alone. Every rank of a job must call it.
std::vector<ProcessFacts> gatherRankFacts(const ProcessFacts& facts);

}  // namespace levelfuse::cli
