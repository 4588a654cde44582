// levelfuse: narrow-band OpenVDB level sets sampled from signed distance functions.
#pragma once

#include <openvdb/openvdb.h>

#include <functional>
#include <string>

namespace levelfuse {

/// Samples a 1-Lipschitz signed distance function (world units, negative
/// inside) into a narrow-band level set of `halfWidth` voxels over the
/// world-space box `bounds`. Only leaf nodes that can hold band voxels are
/// visited, so cost and memory grow with the surface.
openvdb::FloatGrid::Ptr levelSetFromFunction(const std::function<double(const openvdb::Vec3d&)>& signedDistance,
                                             const openvdb::BBoxd& bounds, double voxelSize,
                                             double halfWidth = 3.0, const std::string& name = "surface");

}  // namespace levelfuse
