// The sparse field shared by the ranks of an MPI job, one slab each, steps as
// one process steps the whole field, bit for bit. Run under mpirun with 2 and
// 4 ranks (tests/mpi/CMakeLists.txt); every rank also steps the whole field,
// to compare every step's report, and rank 0 compares the assembled field.

#include "support/TestSupport.h"

#include <levelfuse/geometry/Shapes.h>
#include <levelfuse/levelset/LevelSetFromFunction.h>
#include <levelfuse/levelset/Refine.h>
#include <levelfuse/levelset/SlabField.h>
#include <levelfuse/levelset/SlabTeam.h>
#include <levelfuse/levelset/SparseField.h>
#include <levelfuse/levelset/SpeedTerms.h>
#include <levelfuse/mpi/RankTeam.h>

#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <functional>
#include <string>

namespace levelfuse {
namespace {

using openvdb::Vec3d;

template <typename Speed>
void expectTeamFollowsOneProcess(const openvdb::FloatGrid& levelSet, const Speed& speed, int steps) {
  const mpi::RankTeam team;
  const std::vector<SlabBounds> slabs = balancedSlabs(leafColumns(levelSet.tree()), team.size());
  SlabField slab = SlabField::fromLevelSet(levelSet, slabs[static_cast<std::size_t>(team.rank())]);
  SparseField whole = SparseField::fromLevelSet(levelSet);
  int sameReports = 0;
  for (int s = 1; s <= steps; ++s) {
    const StepResult a = whole.step(speed);
    const StepResult b = stepSlab(slab, speed, team);
    sameReports += a.dt == b.dt && a.rmsChange == b.rmsChange && a.maxChange == b.maxChange &&
                   a.activeSetVoxels == b.activeSetVoxels && a.movedOut == b.movedOut && a.movedIn == b.movedIn;
  }
  EXPECT_EQ(sameReports, steps) << "rank " << team.rank() << ": steps whose report differs from one process's";
  EXPECT_GT(team.ghostBytesSent(), 0u) << "rank " << team.rank();
  const std::vector<PackedLeaves> pieces = team.gather(slab.ownedLeaves(), 0);
  if (team.rank() != 0) return;
  const SparseField parts = SlabField::assemble(pieces, levelSet);
  std::string why;
  EXPECT_TRUE(test::identical(whole.grid(), parts.grid(), &why)) << why;
  EXPECT_EQ(test::voxelsInOtherLayers(whole, parts), 0u) << "band voxels in different layers";
  EXPECT_TRUE(test::identical(*whole.toLevelSet(3.0), *parts.toLevelSet(3.0), &why)) << why;
}

openvdb::FloatGrid::Ptr sample(const std::function<double(const Vec3d&)>& f, const openvdb::BBoxd& box) {
  return levelSetFromFunction(f, box, 1.0);
}

TEST(RankTeam, ASphereUnderCurvatureFlowIsOneProcesssSphere) {
  const auto sphere = sample(shapes::Sphere{Vec3d(0.3, -0.2, 0.1), 17.0}, openvdb::BBoxd(Vec3d(-21), Vec3d(21)));
  expectTeamFollowsOneProcess(*sphere, MeanCurvatureFlow{1.0}, 40);
}

TEST(RankTeam, SpheresMergingAcrossSlabsAreOneProcesssSpheres) {
  const auto twoSpheres = sample(
      [](const Vec3d& p) {
        return std::min(shapes::Sphere{Vec3d(-9.6, 0.2, 0.1), 7.0}(p), shapes::Sphere{Vec3d(9.4, -0.1, 0.3), 7.0}(p));
      },
      openvdb::BBoxd(Vec3d(-19, -10, -10), Vec3d(19, 10, 10)));
  expectTeamFollowsOneProcess(*twoSpheres, ConstantSpeed{ConstantForce{1.0}, 0.1}, 40);
}

TEST(RankTeam, ATorusUnderAForceThatVariesIsOneProcesssTorus) {
  const auto torus = sample(shapes::Torus{Vec3d(0.2, 0.1, -0.2), 14.0, 2.6}, openvdb::BBoxd(Vec3d(-20), Vec3d(20)));
  const ExternalForceSpeed force{[](const Vec3d& x, const Vec3d& n) {
                                   return 0.6 * std::sin(0.3 * x.x()) + 0.4 * std::cos(0.2 * x.y() + 0.1 * x.z()) +
                                          0.1 * n.z();
                                 },
                                 0.8, ForceSampling::kSubcell};
  expectTeamFollowsOneProcess(*torus, force, 40);
}

TEST(RankTeam, EveryRankGetsWhatEachSentIt) {
  // Parcels of different sizes, one empty, and one to itself.
  const mpi::RankTeam team;
  std::vector<PackedLeaves> toEach;
  for (int r = 0; r < team.size(); ++r)
    toEach.push_back(PackedLeaves(static_cast<std::size_t>(1000 * team.rank() + r), static_cast<std::uint8_t>(r + 7 * team.rank())));
  const std::vector<PackedLeaves> fromEach = team.exchange(toEach);
  ASSERT_EQ(fromEach.size(), static_cast<std::size_t>(team.size()));
  for (int from = 0; from < team.size(); ++from) {
    const PackedLeaves& got = fromEach[static_cast<std::size_t>(from)];
    EXPECT_EQ(got, PackedLeaves(static_cast<std::size_t>(1000 * from + team.rank()), static_cast<std::uint8_t>(team.rank() + 7 * from)))
        << "from rank " << from << " at rank " << team.rank();
  }
  EXPECT_THROW(team.exchange({}), std::invalid_argument);
}

TEST(RankTeam, TheRanksRefineAndCutTheFinerGridAsOneProcessRefines) {
  // The coarse slabs are the first cut; the finer grid is cut afresh.
  const mpi::RankTeam team;
  const auto torus = sample(shapes::Torus{Vec3d(0.2, 0.1, -0.2), 14.0, 2.6}, openvdb::BBoxd(Vec3d(-20), Vec3d(20)));
  const ExternalForceSpeed force{[](const Vec3d& x, const Vec3d&) { return 0.6 * std::sin(0.3 * x.x()); }, 0.8,
                                 ForceSampling::kSubcell};
  SparseField whole = SparseField::fromLevelSet(*torus);
  SlabField slab =
      SlabField::fromLevelSet(*torus, balancedSlabs(leafColumns(torus->tree()), team.size())[static_cast<std::size_t>(team.rank())]);
  for (int s = 0; s < 10; ++s) {
    whole.step(force);
    stepSlab(slab, force, team);
  }
  const openvdb::FloatGrid::Ptr fine = refineLevelSet(*whole.toLevelSet(3.0));
  SparseField wholeFine = SparseField::fromLevelSet(*fine);
  slab = refineAcrossTeam(std::move(slab), team, {});
  for (int s = 0; s < 10; ++s) {
    const StepResult a = wholeFine.step(force);
    const StepResult b = stepSlab(slab, force, team);
    EXPECT_TRUE(a.dt == b.dt && a.rmsChange == b.rmsChange && a.activeSetVoxels == b.activeSetVoxels)
        << "step " << s << " at rank " << team.rank();
  }
  const std::vector<PackedLeaves> pieces = team.gather(slab.ownedLeaves(), 0);
  if (team.rank() != 0) return;
  const SparseField parts = SlabField::assemble(pieces, *fine);
  std::string why;
  EXPECT_TRUE(test::identical(wholeFine.grid(), parts.grid(), &why)) << why;
  EXPECT_EQ(test::voxelsInOtherLayers(wholeFine, parts), 0u) << "band voxels in different layers";
}

}  // namespace
}  // namespace levelfuse
