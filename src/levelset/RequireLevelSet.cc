// levelfuse: what every entry point that takes a level set requires of it.

#include <levelfuse/levelset/RequireLevelSet.h>

#include <cmath>
#include <stdexcept>

namespace levelfuse {

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
  return {};
}

void requireLevelSet(const openvdb::FloatGrid& grid, const std::string& who) {
  const std::string problem = levelSetProblem(grid);
  if (!problem.empty()) throw std::invalid_argument(who + ": " + problem);
}

}  // namespace levelfuse
