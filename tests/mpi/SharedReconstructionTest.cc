// A reconstruction whose evolution the ranks of an MPI job share, one slab
// of every grid each, gives one process's result bit for bit, at rank 0.

#include "support/TestSupport.h"

#include <levelfuse/geometry/Shapes.h>
#include <levelfuse/mpi/RankTeam.h>
#include <levelfuse/recon/Reconstructor.h>
#include <levelfuse/scan/Synth.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

namespace levelfuse {
namespace {

using openvdb::Vec3d;

/// Six noisy views of a torus, with outliers: the data term pulls, the prior smooths.
std::vector<RangeMap> noisyTorus() {
  const shapes::Torus torus{Vec3d(0.013, -0.021, 0.007), 0.8, 0.3};
  std::vector<RangeMap> maps;
  std::uint64_t seed = 1;
  for (const synth::View& view : synth::sixAxisViews(Vec3d(0.0), 2.4, 120)) {
    synth::Noise noise;
    noise.gaussianSigma = 0.01;
    noise.seed = seed++;
    maps.push_back(synth::renderDistanceFunction(torus, view, noise, 0.01));
  }
  return maps;
}

void expectSharedRunIsOneProcesssRun(DataTermSource source) {
  ReconstructionOptions options;
  options.voxelSize = 0.02;
  options.levels = 3;
  options.dataTerm = source;
  const Reconstructor reconstructor(noisyTorus(), options);
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
