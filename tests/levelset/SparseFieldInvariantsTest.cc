// The Appendix's invariants, checked after every step of randomised runs.

#include "support/TestSupport.h"

#include <levelfuse/geometry/Shapes.h>
#include <levelfuse/levelset/Invariants.h>
#include <levelfuse/levelset/LevelSetFromFunction.h>
#include <levelfuse/levelset/SparseField.h>
#include <levelfuse/levelset/SpeedTerms.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace levelfuse {
namespace {

struct RandomWorld {
  std::vector<shapes::Sphere> spheres;
  double operator()(const openvdb::Vec3d& p) const {
    double d = std::numeric_limits<double>::max();
    for (const auto& s : spheres) d = std::min(d, s(p));
    return d;
  }
};

/// A smooth random force field: a sum of plane waves plus a constant.
struct WaveForce {
  std::vector<openvdb::Vec3d> k;
  std::vector<double> phase, amplitude;
  double offset = 0.0;
  double operator()(const openvdb::Vec3d& x, const openvdb::Vec3d&) const {
    double f = offset;
    for (std::size_t i = 0; i < k.size(); ++i) f += amplitude[i] * std::sin(k[i].dot(x) + phase[i]);
    return f;
  }
};

class RandomRun : public ::testing::TestWithParam<unsigned> {};

TEST_P(RandomRun, InvariantsHoldAfterEveryStep) {
  std::mt19937 rng(GetParam());
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  RandomWorld world;
  const int count = 2 + static_cast<int>(GetParam() % 4);
  for (int i = 0; i < count; ++i)
    world.spheres.push_back({openvdb::Vec3d(24 * uniform(rng), 24 * uniform(rng), 24 * uniform(rng)),
                             3.0 + 7.0 * uniform(rng)});
  const auto initial = levelSetFromFunction(world, openvdb::BBoxd(openvdb::Vec3d(-12), openvdb::Vec3d(40)), 1.0);
  SparseField field = SparseField::fromLevelSet(*initial);
  ASSERT_TRUE(checkInvariants(field).ok());

  WaveForce force;
  for (int i = 0; i < 3; ++i) {
    force.k.push_back(openvdb::Vec3d(uniform(rng) - 0.5, uniform(rng) - 0.5, uniform(rng) - 0.5) * 0.8);
    force.phase.push_back(6.28 * uniform(rng));
    force.amplitude.push_back(0.5 + uniform(rng));
  }
  force.offset = uniform(rng) - 0.5;
  ExternalForceSpeed speed{ExternalForce(force), 0.5 * uniform(rng),
                           GetParam() % 2 ? ForceSampling::kSubcell : ForceSampling::kGridPoint};

  std::size_t conflicts = 0, moves = 0;
  for (int step = 0; step < 80; ++step) {
    const StepResult r = field.step(speed);
    conflicts += r.conflicts;
    moves += r.movedIn + r.movedOut;
    ASSERT_LT(r.maxChange, 0.5 * field.voxelSize()) << "step " << step;
    const InvariantReport report = checkInvariants(field);
    ASSERT_TRUE(report.ok()) << "step " << step << ": " << report.firstViolation;
    ASSERT_EQ(report.activeSetVoxels, r.activeSetVoxels);
    // Efficient except at singularities: a small fraction at most.
    ASSERT_LE(report.inefficientActive, report.activeSetVoxels / 50 + 8) << "step " << step;
  }
  EXPECT_GT(moves, 100u) << "the surface hardly moved; the run tests nothing";
  RecordProperty("conflicts", static_cast<int>(conflicts));
}

INSTANTIATE_TEST_SUITE_P(Seeds, RandomRun, ::testing::Range(1u, 9u));

TEST(SparseFieldInvariants, ShrinkingToNothingLeavesNoSurface) {
  SparseField field = SparseField::fromLevelSet(*test::makeSphere(4.0, openvdb::Vec3d(0.3, 0.1, -0.2)));
  const ConstantSpeed shrink{ConstantForce{-1.0}};
  for (int step = 0; step < 40 && field.stats().activeSetVoxels > 0; ++step) {
    field.step(shrink);
    const InvariantReport report = checkInvariants(field);
    ASSERT_TRUE(report.ok()) << "step " << step << ": " << report.firstViolation;
  }
  EXPECT_EQ(field.stats().activeSetVoxels, 0u);
  EXPECT_EQ(field.stats().leafNodes, 0u);
  EXPECT_GT(field.grid().tree().getValue(openvdb::Coord(0)), 0.0f);
}

TEST(SparseFieldInvariants, AStepNeverMovesAValueByHalfAVoxel) {
  SparseField field = SparseField::fromLevelSet(*test::makeSphere(10.0, openvdb::Vec3d(0.0), 0.25));
  const ConstantSpeed fast{ConstantForce{100.0}};
  const StepResult r = field.step(fast);
  // The fastest active point moves exactly maxStepChange voxels (Eq. 31)...
  EXPECT_NEAR(r.maxChange, 0.45 * 0.25, 1e-5);
  EXPECT_NEAR(r.dt, 0.45 * 0.25 / r.maxSpeed, 1e-9);
  // ...and the speed is F |grad psi| with an up-wind |grad psi| of about 1 to sqrt(3).
  EXPECT_GE(r.maxSpeed, 100.0);
  EXPECT_LE(r.maxSpeed, 100.0 * std::sqrt(3.0));
  // Curvature flow is limited by the stability of the explicit term.
  const StepResult c = field.step(MeanCurvatureFlow{2.0});
  EXPECT_LE(c.dt, 0.25 * 0.25 / 4.0 / 2.0 + 1e-9);
}

}  // namespace
}  // namespace levelfuse
