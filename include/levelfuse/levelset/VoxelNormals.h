// levelfuse: a level set's outward normal at its voxels.
#pragma once

#include <openvdb/openvdb.h>

namespace levelfuse {

/// The outward unit normals of a level set at its voxels: the gradient of phi
/// by central differences, each taken along the world step of its index axis
/// (right for any linear transform).
class VoxelNormals {
 public:
  explicit VoxelNormals(const openvdb::FloatGrid& levelSet) {
    const openvdb::Vec3d origin = levelSet.indexToWorld(openvdb::Vec3d(0.0));
    for (int a = 0; a < 3; ++a) {
      openvdb::Vec3d unit(0.0);
      unit[a] = 1.0;
      mAxes[a] = levelSet.indexToWorld(unit) - origin;
    }
  }

  /// The unit normal at voxel `ijk`, read through `phi` (an accessor of the
  /// level set); false where the differences vanish.
  bool at(const openvdb::FloatGrid::ConstAccessor& phi, const openvdb::Coord& ijk, openvdb::Vec3d& normal) const {
    normal = openvdb::Vec3d(0.0);
    for (int a = 0; a < 3; ++a) {
      openvdb::Coord step(0);
      step[a] = 1;
      normal += mAxes[a] * (phi.getValue(ijk + step) - phi.getValue(ijk - step));
    }
    return normal.normalize();
  }

 private:
  openvdb::Vec3d mAxes[3];
};

}  // namespace levelfuse
