// levelfuse: the one precondition check of every entry point that takes a
// level set, in the manner of OpenVDB's level-set tools.
#pragma once

#include <openvdb/openvdb.h>

#include <string>

namespace levelfuse {

/// "the grid 'name'", or "the grid" for an unnamed one: how messages name a grid.
std::string describeGrid(const openvdb::GridBase& grid);

/// What keeps `grid`'s voxels from being the uniform, linearly placed cubes
/// the engine works on (a frustum or a stretched transform), with a hint;
/// empty if nothing. Part of levelSetProblem; masks need it too.
std::string transformProblem(const openvdb::GridBase& grid);

/// What keeps `grid` from being a narrow-band level set as OpenVDB's tools
/// make them, with a hint of what to do; empty if nothing. A level set has
/// class GRID_LEVEL_SET (a fog volume: convert it with
/// openvdb::tools::fogToSdf; signed distances of another class: set the
/// class), uniform (cubic) voxels and a linear transform (resample a frustum
/// or stretched grid first), a positive, finite background (the band's
/// half-width in world units) and finite values only (no NaN, no infinity),
/// the one check that reads every voxel: a parallel pass over the leaves.
std::string levelSetProblem(const openvdb::FloatGrid& grid);

/// Throws std::invalid_argument "who: <the problem>" unless `grid` is a level
/// set (levelSetProblem); `who` names the entry point, e.g. "refineLevelSet".
void requireLevelSet(const openvdb::FloatGrid& grid, const std::string& who);

}  // namespace levelfuse
