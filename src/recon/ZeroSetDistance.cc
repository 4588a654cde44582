// levelfuse: distances from points to a level set's zero set, searched in
// growing cubes around them.

#include "ZeroSetDistance.h"

#include <levelfuse/core/Parallel.h>
#include <levelfuse/geometry/NearestTriangle.h>
#include <levelfuse/levelset/Mesh.h>

#include <openvdb/tools/VolumeToSpheres.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace levelfuse::detail {

namespace {

/// The voxels within `reach` voxels of each point, along each axis.
openvdb::BoolGrid cubesAround(const openvdb::FloatGrid& levelSet, const std::vector<openvdb::Vec3d>& points,
                              const std::vector<std::size_t>& which, int reach) {
  openvdb::BoolGrid cubes(false);
  cubes.setTransform(levelSet.transform().copy());
  for (std::size_t i : which) {
    const openvdb::Coord centre = openvdb::Coord::round(levelSet.worldToIndex(points[i]));
    cubes.tree().sparseFill(openvdb::CoordBBox(centre.offsetBy(-reach), centre.offsetBy(reach)), true, true);
  }
  return cubes;
}

/// The reach (voxels) at which the cube around each of the points holds the
/// whole band of the level set.
int reachOfTheWholeBand(const openvdb::FloatGrid& levelSet, const std::vector<openvdb::Vec3d>& points,
                        const std::vector<std::size_t>& which) {
  const openvdb::CoordBBox band = levelSet.evalActiveVoxelBoundingBox();
  if (band.empty()) return 0;
  openvdb::Int64 reach = 0;
  for (std::size_t i : which) {
    const openvdb::Coord centre = openvdb::Coord::round(levelSet.worldToIndex(points[i]));
    for (int axis = 0; axis < 3; ++axis)
      reach = std::max({reach, openvdb::Int64(centre[axis]) - band.min()[axis],
                        openvdb::Int64(band.max()[axis]) - centre[axis]});
  }
  return static_cast<int>(std::min<openvdb::Int64>(reach, std::numeric_limits<int>::max() / 2));
}

/// The distances from the `open` points to the nearest vertex of the whole
/// zero set's mesh (OpenVDB's ClosestSurfacePoint, which keeps its vertices
/// alone: a voxel or so apart on the zero set, so that this far out the
/// distance is at most a few hundredths of a voxel too long).
void distancesToTheWholeZeroSet(const openvdb::FloatGrid& levelSet, const std::vector<openvdb::Vec3d>& points,
                                const std::vector<std::size_t>& open, std::vector<double>& distance) {
  const auto surface = openvdb::tools::ClosestSurfacePoint<openvdb::FloatGrid>::create(levelSet);
  if (!surface) return;
  std::vector<openvdb::Vec3R> searched;
  for (std::size_t i : open) searched.push_back(points[i]);
  std::vector<float> found;
  if (!surface->search(searched, found)) return;
  for (std::size_t k = 0; k < open.size(); ++k) distance[open[k]] = found[k];
}

}  // namespace

std::vector<double> distancesToZeroSet(const openvdb::FloatGrid& levelSet, const std::vector<openvdb::Vec3d>& points,
                                       int firstReach) {
  const double voxel = levelSet.voxelSize()[0];
  std::vector<double> distance(points.size(), std::numeric_limits<double>::infinity());
  std::vector<std::size_t> open(points.size());
  for (std::size_t i = 0; i < open.size(); ++i) open[i] = i;
  const double bandVoxels = static_cast<double>(levelSet.activeVoxelCount());
  for (int reach = std::max(firstReach, 2); !open.empty(); reach *= 2) {
    // Once the cubes would hold more voxels than the band, or hold all of
    // it, the rest are measured against the whole zero set, once.
    const double side = 2.0 * reach + 1.0;
    if (static_cast<double>(open.size()) * side * side * side >= bandVoxels ||
        reach >= reachOfTheWholeBand(levelSet, points, open)) {
      distancesToTheWholeZeroSet(levelSet, points, open, distance);
      break;
    }
    const TriangleMesh mesh = meshFromLevelSet(levelSet, 0.0, cubesAround(levelSet, points, open, reach));
    if (mesh.triangleCount() > 0) {
      const NearestTriangle nearest(mesh.xyz, mesh.triangles);
      parallelFor(open.size(), 256, [&](std::size_t begin, std::size_t end) {
        for (std::size_t k = begin; k < end; ++k) distance[open[k]] = nearest.distance(points[open[k]]);
      });
    }
    // The zero set within a cube is all meshed but for cells that straddle
    // its faces: a surface point nearer than two voxels short of the reach
    // was found. The other points look again, twice as far.
    const double surelyFound = (reach - 2) * voxel;
    open.erase(std::remove_if(open.begin(), open.end(), [&](std::size_t i) { return distance[i] <= surelyFound; }),
               open.end());
  }
  return distance;
}

}  // namespace levelfuse::detail
