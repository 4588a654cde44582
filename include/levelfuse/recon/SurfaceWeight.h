// levelfuse: how well the scans observed each part of a surface, as a grid
// beside its level set.
//
// A level set must be closed; the scans need not have seen all of it. Space
// carving closes what no scan saw (the back of a room's walls, the ceiling
// no depth frame looked at). The weight grid says, per voxel of the level
// set's narrow band, how many readings support the surface there: the
// readings N~ = sum w_j that face it (Eq. 37: scans whose line of sight meets
// the surface from its outside), each counted with its window w_j at the
// voxel, the count the data force is normalised by (recon/DataSpeed.h). Its
// unit is thus "readings": 0 where no reading's window reaches (or only
// readings from behind the surface), 1 where one reading saw it, about k
// where k readings did, whatever their depth and noise.
#pragma once

#include <levelfuse/core/Interrupter.h>
#include <levelfuse/scan/DataTermGrids.h>
#include <levelfuse/scan/ForceField.h>
#include <levelfuse/scan/RangeMap.h>

#include <openvdb/openvdb.h>

#include <string>
#include <vector>

namespace levelfuse {

/// The name of the weight grid a reconstruction writes beside its level set.
inline constexpr const char* kWeightGridName = "weight";

/// A surface counts as observed where at least this many readings face it
/// (meshes and previews of scenes leave the rest out). A tenth: a surface that
/// space carving closed, which no reading faces, counts 0; where a reading's
/// window just reaches past the edge of what it saw, the count falls
/// continuously to 0, to a tenth at 2.1 epsilon (docs/RECONSTRUCTION.md).
inline constexpr double kObservedWeight = 0.1;

/// The number of readings that face the surface at
/// every active voxel of `levelSet`'s narrow band (GRID_UNKNOWN, named
/// kWeightGridName, the level set's transform, background 0, with levelfuse_*
/// metadata saying what it is). It holds the leaves of the band where some
/// reading faces the surface, with their active voxels; a leaf that no
/// reading faces (the unseen faces of a scene) is left out, its weight the
/// background 0, so the grid grows with what the scans saw. The outward normal at a
/// voxel is the level set's gradient there. Parallel over leaf nodes and
/// deterministic. Throws std::invalid_argument for a grid that is not a level
/// set, Interrupted if `interrupter` asks to stop.
openvdb::FloatGrid::Ptr surfaceWeight(const openvdb::FloatGrid& levelSet, const ForceField& data,
                                      const Interrupter& interrupter = {});
openvdb::FloatGrid::Ptr surfaceWeight(const openvdb::FloatGrid& levelSet, const DataTermGrids& data,
                                      const Interrupter& interrupter = {});

/// True when every scan is of a scene around its scanner (RangeMap::ofAScene:
/// depth frames, spherical scans that surround their scanner): the surface is
/// a scene seen from inside (a room, a desk, a street) rather than an object
/// seen from around it, and what no scan saw is left out of meshes and previews by
/// default.
bool scansOfAScene(const std::vector<RangeMap>& maps);

}  // namespace levelfuse
