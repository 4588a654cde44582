// The sparse field shared by the ranks of an MPI job, one slab each, steps as
// one process steps the whole field, bit for bit. Run under mpirun with 2 and
// 4 ranks (tests/mpi/CMakeLists.txt); every rank also steps the whole field,
// to compare every step's report, and rank 0 compares the assembled field.

#include "support/TestSupport.h"

#include <levelfuse/geometry/Shapes.h>
#include <levelfuse/levelset/LevelSetFromFunction.h>
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

}  // namespace
}  // namespace levelfuse
