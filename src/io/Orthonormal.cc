// levelfuse: rotations read from files.

#include "Orthonormal.h"

#include <algorithm>
#include <cmath>

namespace levelfuse::io {

double orthonormalityError(const openvdb::math::Mat3d& m) {
  const openvdb::math::Mat3d products = m * m.transpose();
  double largest = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) largest = std::max(largest, std::fabs(products(i, j) - (i == j ? 1.0 : 0.0)));
  return largest;
}

openvdb::math::Mat3d nearestRotation(openvdb::math::Mat3d m) {
  // Newton's iteration converges quadratically from near a rotation: eight
  // steps take an error of a part in a hundred (a tracked camera's pose)
  // below rounding.
  for (int iteration = 0; iteration < 8; ++iteration) m = (m + m.inverse().transpose()) * 0.5;
  return m;
}

}  // namespace levelfuse::io
