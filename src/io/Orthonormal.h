// levelfuse: how near a matrix read from a file is to a rotation, and the
// rotation nearest to it (private to the readers).
#pragma once

#include <openvdb/math/Mat3.h>

namespace levelfuse::io {

/// How far the rows of `m` are from orthonormal: the largest |(m m^T - I)_ij|
/// (0 for a rotation or a mirror).
double orthonormalityError(const openvdb::math::Mat3d& m);

/// The rotation nearest to `m`, which must be orthonormal to within a part in
/// a hundred with a positive determinant: a rotation written with six
/// decimals, or a tracked camera's, comes back orthonormal to rounding (polar
/// decomposition by Newton's iteration).
openvdb::math::Mat3d nearestRotation(openvdb::math::Mat3d m);

}  // namespace levelfuse::io
