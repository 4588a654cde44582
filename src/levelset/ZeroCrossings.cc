// levelfuse: zero crossings along grid edges.

#include <levelfuse/levelset/RequireLevelSet.h>
#include <levelfuse/levelset/ZeroCrossings.h>


#include <levelfuse/core/Parallel.h>

namespace levelfuse {

std::vector<openvdb::Vec3d> zeroCrossings(const openvdb::FloatGrid& grid) {
  requireLevelSet(grid, "zeroCrossings");
  using LeafT = openvdb::FloatTree::LeafNodeType;
  std::vector<const LeafT*> leaves;
  grid.tree().getNodes(leaves);
  std::vector<std::vector<openvdb::Vec3d>> found(leaves.size());
  const openvdb::math::Transform& xform = grid.transform();
  parallelFor(leaves.size(), 1, [&](std::size_t begin, std::size_t end) {
    openvdb::FloatGrid::ConstAccessor acc = grid.getConstAccessor();
    for (std::size_t l = begin; l != end; ++l) {
      for (auto it = leaves[l]->cbeginValueOn(); it; ++it) {
        const openvdb::Coord ijk = it.getCoord();
        const float a = *it;
        for (int axis = 0; axis < 3; ++axis) {
          openvdb::Coord step(0);
          step[axis] = 1;
          // Each edge once: towards +axis always, towards -axis only if that
          // neighbour is not active itself.
          const openvdb::Coord up = ijk + step, down = ijk - step;
          const float b = acc.getValue(up);
          if ((a < 0.0f) != (b < 0.0f)) {
            const double t = static_cast<double>(a) / (static_cast<double>(a) - static_cast<double>(b));
            found[l].push_back(xform.indexToWorld(ijk.asVec3d() + t * step.asVec3d()));
          }
          if (!acc.isValueOn(down)) {
            const float c = acc.getValue(down);
            if ((a < 0.0f) != (c < 0.0f)) {
              const double t = static_cast<double>(a) / (static_cast<double>(a) - static_cast<double>(c));
              found[l].push_back(xform.indexToWorld(ijk.asVec3d() - t * step.asVec3d()));
            }
          }
        }
      }
    }
  });
  std::vector<openvdb::Vec3d> points;
  for (auto& f : found) points.insert(points.end(), f.begin(), f.end());
  return points;
}

}  // namespace levelfuse
