// Finite differences of Stencil.h against analytic answers.

#include <levelfuse/levelset/SpeedTerms.h>
#include <levelfuse/levelset/Stencil.h>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

namespace levelfuse {
namespace {

Stencil sample(const std::function<double(double, double, double)>& f, double x, double y, double z, double h) {
  Stencil s;
  s.h = static_cast<float>(h);
  for (int p = 0; p < Stencil::kSize; ++p) {
    const int* d = Stencil::kOffset[p];
    s.u[p] = static_cast<float>(f(x + d[0] * h, y + d[1] * h, z + d[2] * h));
  }
  return s;
}

TEST(Stencil, CurvatureTermOfSphereIsTwoOverRadius) {
  const auto sphere = [](double x, double y, double z) { return std::sqrt(x * x + y * y + z * z) - 20.0; };
  for (const auto& p : {openvdb::Vec3d(20, 0, 0), openvdb::Vec3d(11.5, 11.5, 11.5), openvdb::Vec3d(3, -12, 15.6)}) {
    const Stencil s = sample(sphere, p.x(), p.y(), p.z(), 1.0);
    EXPECT_NEAR(meanCurvatureTerm(s), 2.0 / p.length(), 2e-3) << p;
  }
}

TEST(Stencil, CurvatureTermIsInvariantToScale) {
  // Same sphere in world units with 0.1 voxels: the term is in world units.
  const auto sphere = [](double x, double y, double z) { return std::sqrt(x * x + y * y + z * z) - 2.0; };
  const Stencil s = sample(sphere, 2.0, 0.0, 0.0, 0.1);
  EXPECT_NEAR(meanCurvatureTerm(s), 1.0, 2e-3);
}

TEST(Stencil, CurvatureTermOfCylinderIsOneOverRadius) {
  const auto cylinder = [](double x, double y, double) { return std::sqrt(x * x + y * y) - 10.0; };
  const Stencil s = sample(cylinder, 7.0, 7.0, 3.0, 1.0);
  EXPECT_NEAR(meanCurvatureTerm(s), 1.0 / std::sqrt(98.0), 2e-3);
}

TEST(Stencil, CurvatureTermAtAnIsolatedExtremumCollapsesIt) {
  // A lone inside voxel: its neighbours are all equal, the gradient vanishes.
  Stencil s;
  for (float& u : s.u) u = 0.7f;
  s.u[Stencil::kCentre] = -0.3f;
  for (int p = Stencil::kXmYm; p < Stencil::kSize; ++p) s.u[p] = 1.7f;
  // The inside must shrink: d psi/dt = kappa |grad psi| > 0.
  EXPECT_NEAR(meanCurvatureTerm(s), (2.0f / 3.0f) * 6.0f, 1e-5);
  // u = r^2 / 2 sampled around its minimum: kappa |grad u| = 2 on every level set.
  const auto bowl = [](double x, double y, double z) { return 0.5 * (x * x + y * y + z * z); };
  Stencil b = sample(bowl, 0.0, 0.0, 0.0, 1.0);
  EXPECT_NEAR(meanCurvatureTerm(b), 2.0, 1e-5);
}

TEST(Stencil, UpwindGradientPicksTheSideTheFrontComesFrom) {
  // A ridge u = -|x|: forward and backward differences disagree at x = 0.
  const auto ridge = [](double x, double, double) { return -std::fabs(x); };
  const Stencil s = sample(ridge, 0.0, 0.0, 0.0, 1.0);
  // Growing (F > 0): max(D-, 0) = 1 and min(D+, 0) = -1 -> sqrt(2).
  EXPECT_NEAR(upwindGradientMagnitude(s, 1.0f), std::sqrt(2.0), 1e-6);
  // Shrinking (F < 0): min(D-, 0) = 0 and max(D+, 0) = 0.
  EXPECT_NEAR(upwindGradientMagnitude(s, -1.0f), 0.0, 1e-6);
  // On a plane both sides agree and give |grad u| = 1.
  const auto plane = [](double x, double y, double z) { return (2.0 * x - y + 2.0 * z) / 3.0 + 0.2; };
  const Stencil p = sample(plane, 1.0, 2.0, 3.0, 1.0);
  EXPECT_NEAR(upwindGradientMagnitude(p, 1.0f), 1.0, 1e-6);
  EXPECT_NEAR(upwindGradientMagnitude(p, -1.0f), 1.0, 1e-6);
}

TEST(Stencil, MaxAbsPicksTheSteeperDifference) {
  EXPECT_EQ(maxAbs(1.0f, -3.0f), -3.0f);
  EXPECT_EQ(maxAbs(-4.0f, 2.0f), -4.0f);
  EXPECT_EQ(maxAbs(2.0f, -2.0f), 0.0f);  // tie: their mean (Eq. 35)
}

TEST(Stencil, SubcellOffsetLandsOnAPlaneExactly) {
  // For a linear u, x^ of Eq. 34 is the exact foot point on the zero plane.
  const openvdb::Vec3d n = openvdb::Vec3d(1.0, 2.0, -2.0) / 3.0;
  const double c = 0.3;
  const auto plane = [&](double x, double y, double z) { return n.dot(openvdb::Vec3d(x, y, z)) - c; };
  const openvdb::Vec3d x(0.4, -0.1, 0.2);
  const Stencil s = sample(plane, x.x(), x.y(), x.z(), 1.0);
  const openvdb::Vec3d foot = x + openvdb::Vec3d(subcellOffset(s));
  EXPECT_NEAR(plane(foot.x(), foot.y(), foot.z()), 0.0, 1e-6);
}

TEST(Stencil, SubcellOffsetWithoutGradientIsZero) {
  Stencil s;
  for (float& u : s.u) u = 0.25f;
  EXPECT_EQ(subcellOffset(s), openvdb::Vec3f(0.0f));
}

TEST(Stencil, SubcellOffsetOnASphereIsCloseToTheSurface) {
  const auto sphere = [](double x, double y, double z) { return std::sqrt(x * x + y * y + z * z) - 30.0; };
  const openvdb::Vec3d x(17.0, 17.0, 17.0);  // 0.56 voxel inside, diagonal normal
  const Stencil s = sample(sphere, x.x(), x.y(), x.z(), 1.0);
  const openvdb::Vec3d foot = x + openvdb::Vec3d(subcellOffset(s));
  // First-order (Eq. 34) with one-sided differences: within a fiftieth of a voxel here.
  EXPECT_LT(std::fabs(sphere(foot.x(), foot.y(), foot.z())), 0.02);
}

}  // namespace
}  // namespace levelfuse
