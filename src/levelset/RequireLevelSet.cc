// levelfuse: what every entry point that takes a level set requires of it.

#include <levelfuse/levelset/RequireLevelSet.h>

#include <levelfuse/core/Parallel.h>

#include <cmath>
#include <optional>
#include <stdexcept>
#include <vector>

namespace levelfuse {

namespace {

/// The first voxel or tile, in the tree's order, whose value is NaN or
/// infinite: a leaf's voxels (active or not, as meshing and the engine read
/// both), then the tiles of the nodes above the leaves.
std::optional<openvdb::Coord> firstNonFiniteValue(const openvdb::FloatGrid& grid) {
  std::vector<const openvdb::FloatTree::LeafNodeType*> leaves;
  grid.tree().getNodes(leaves);
  constexpr openvdb::Index kNone = openvdb::FloatTree::LeafNodeType::SIZE;
  std::vector<openvdb::Index> firstInLeaf(leaves.size(), kNone);
  parallelFor(leaves.size(), 16, [&](std::size_t begin, std::size_t end) {
    for (std::size_t l = begin; l != end; ++l) {
      const float* values = leaves[l]->buffer().data();
      for (openvdb::Index o = 0; o < kNone; ++o)
        if (!std::isfinite(values[o])) {
          firstInLeaf[l] = o;
          break;
        }
    }
  });
  for (std::size_t l = 0; l < leaves.size(); ++l)
    if (firstInLeaf[l] != kNone) return leaves[l]->offsetToGlobalCoord(firstInLeaf[l]);
  openvdb::FloatTree::ValueAllCIter tile = grid.tree().cbeginValueAll();
  tile.setMaxDepth(openvdb::FloatTree::ValueAllCIter::LEAF_DEPTH - 1);
  for (; tile; ++tile)
    if (!std::isfinite(*tile)) return tile.getCoord();
  return std::nullopt;
}

}  // namespace

std::string describeGrid(const openvdb::GridBase& grid) {
  return grid.getName().empty() ? std::string("the grid") : "the grid '" + grid.getName() + "'";
}

std::string transformProblem(const openvdb::GridBase& grid) {
  if (!grid.transform().isLinear())
    return describeGrid(grid) + " has a non-linear (frustum) transform; resample it to a linear one first "
                                "(openvdb::tools::resampleToMatch)";
  if (!grid.hasUniformVoxels())
    return describeGrid(grid) + " has non-uniform voxels; resample it to cubic voxels first "
                                "(openvdb::tools::resampleToMatch)";
  return {};
}

std::string levelSetProblem(const openvdb::FloatGrid& grid) {
  const std::string what = describeGrid(grid);
  if (grid.getGridClass() == openvdb::GRID_FOG_VOLUME)
    return what + " is a fog volume, not a level set; convert it with openvdb::tools::fogToSdf";
  if (grid.getGridClass() != openvdb::GRID_LEVEL_SET)
    return what + " is not a level set (its class is " + openvdb::GridBase::gridClassToString(grid.getGridClass()) +
           "); if it holds signed distances, negative inside, set its class to openvdb::GRID_LEVEL_SET";
  if (std::string problem = transformProblem(grid); !problem.empty()) return problem;
  if (!(grid.background() > 0.0f) || !std::isfinite(grid.background()))
    return what + " has a background of " + std::to_string(grid.background()) +
           "; a level set's background is its narrow band's half-width in world units, positive "
           "(openvdb::tools::changeLevelSetBackground)";
  if (const std::optional<openvdb::Coord> voxel = firstNonFiniteValue(grid))
    return what + " holds a value that is not finite at voxel " + voxel->asVec3i().str() +
           "; a level set holds finite distances (openvdb::tools::checkLevelSet finds such values)";
  return {};
}

void requireLevelSet(const openvdb::FloatGrid& grid, const std::string& who) {
  const std::string problem = levelSetProblem(grid);
  if (!problem.empty()) throw std::invalid_argument(who + ": " + problem);
}

}  // namespace levelfuse
