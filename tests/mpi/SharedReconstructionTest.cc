// A reconstruction whose evolution the ranks of an MPI job share, one slab
// of every grid each, gives one process's result bit for bit, at rank 0.

#include "support/NoisyTorus.h"
#include "support/TestSupport.h"

#include <levelfuse/mpi/RankTeam.h>
#include <levelfuse/recon/Reconstructor.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

namespace levelfuse {
namespace {

void expectSharedRunIsOneProcesssRun(DataTermSource source) {
  ReconstructionOptions options;
  options.voxelSize = 0.02;
  options.levels = 3;
  options.dataTerm = source;
  const Reconstructor reconstructor(test::noisyTorusScans(), options);
  const mpi::RankTeam team;
  const ReconstructionResult alone = reconstructor.run();
  const ReconstructionResult shared = reconstructor.run({}, {}, &team);
  ASSERT_EQ(alone.levels.size(), shared.levels.size());
  for (std::size_t l = 0; l < alone.levels.size(); ++l) {
    EXPECT_EQ(alone.levels[l].iterations, shared.levels[l].iterations) << "grid " << l << ", rank " << team.rank();
    EXPECT_EQ(alone.levels[l].activeSetVoxels, shared.levels[l].activeSetVoxels) << "grid " << l;
    EXPECT_EQ(alone.levels[l].bandVoxels, shared.levels[l].bandVoxels) << "grid " << l;
  }
  if (team.rank() != 0) {
    EXPECT_FALSE(shared.levelSet) << "only the first rank holds the result";
    return;
  }
  ASSERT_TRUE(shared.levelSet && shared.weight);
  std::string why;
  EXPECT_TRUE(test::identical(*alone.levelSet, *shared.levelSet, &why)) << why;
  EXPECT_TRUE(test::identical(*alone.weight, *shared.weight, &why)) << why;
  EXPECT_GT(alone.levels.back().iterations, 4);
}

TEST(SharedReconstruction, TheDataTermFromTheMapsGivesOneProcesssSurface) {
  expectSharedRunIsOneProcesssRun(DataTermSource::kPerMap);
}

TEST(SharedReconstruction, TheDataTermFromGridsGivesOneProcesssSurface) {
  expectSharedRunIsOneProcesssRun(DataTermSource::kGrids);
}

}  // namespace
}  // namespace levelfuse
