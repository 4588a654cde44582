// Checks of what a range map says about a point, shared by the range map tests.
#pragma once

#include <levelfuse/scan/RangeMap.h>

#include <gtest/gtest.h>

namespace levelfuse::test {

/// Expects `s`, the map's sample at world point `x`, to hold the gradient of
/// D that central differences of D with steps of `h` along each world axis
/// give, each component within `tolerance`.
inline void expectGradDByDifferences(const RangeMap& map, const openvdb::Vec3d& x, const RangeSample& s, double h,
                                     double tolerance) {
  for (int a = 0; a < 3; ++a) {
    openvdb::Vec3d step(0.0);
    step[a] = h;
    RangeSample plus, minus;
    ASSERT_TRUE(map.sample(x + step, plus)) << "axis " << a;
    ASSERT_TRUE(map.sample(x - step, minus)) << "axis " << a;
    EXPECT_NEAR(s.gradD[a], (plus.D - minus.D) / (2 * h), tolerance) << "axis " << a;
  }
}

}  // namespace levelfuse::test
