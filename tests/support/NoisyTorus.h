// Six noisy views of a torus, the scans the tests of a shared reconstruction
// (a team of threads, tests/recon; MPI ranks, tests/mpi) reconstruct.
#pragma once

#include <levelfuse/scan/RangeMap.h>

#include <vector>

namespace levelfuse::test {

/// Six views of a torus (radii 0.8 and 0.3) 120 x 120 pixels, Gaussian
/// range noise of 0.01: the data term pulls, the prior smooths.
std::vector<RangeMap> noisyTorusScans();

}  // namespace levelfuse::test
