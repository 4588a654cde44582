// A team of slabs (levelset/SlabTeam.h) run as threads of one process, one
// rank each: the team's code paths (stepSlab, refineAcrossTeam, the
// reconstruction on a team) tested without MPI, and under AddressSanitizer,
// which the MPI build leaves out. Every collective is an exchange of parcels
// between all ranks at a barrier.
#pragma once

#include <levelfuse/levelset/SlabTeam.h>

#include <functional>

namespace levelfuse::test {

/// Runs `body` on `size` threads at once, each with its own rank of one team.
/// If a rank throws, the others stop at their next collective, and the first
/// exception is rethrown here once every thread has ended.
void runOnThreadTeam(int size, const std::function<void(const SlabTeam&)>& body);

}  // namespace levelfuse::test
