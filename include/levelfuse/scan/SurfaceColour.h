// levelfuse: the colour the scans saw on a surface, as a grid beside its level
// set (Houdini's convention: a Vec3f grid named "Cd", from 0 to 1).
//
// At an active voxel x of a level set's narrow band, with N the unit outward
// normal there (the level set's gradient), the surface point nearest x is
// y = x - phi(x) N. Every range map that carries colour and sees y from the
// surface's outside (its line of sight against N: the facing check of
// Eq. 37) gives the colour along its line of sight through y
// (RangeMap::colourAt), weighted as its reading's term is in the data term at
// y: c w gamma, the window w(D) (Eqs. 8-9) times the confidence c (Eq. 38)
// times the ray density gamma (Eq. 13). So a map whose reading lies far in
// front of y (something in between hid the surface) gives none, and the
// nearer, denser and less noisy readings weigh more:
//
//   Cd(x) = sum_j c_j w_j gamma_j rgb_j(y) / sum_j c_j w_j gamma_j
//
// The maps are visited once each, one at a time.
#pragma once

#include <levelfuse/core/Interrupter.h>
#include <levelfuse/levelset/Mesh.h>
#include <levelfuse/scan/DataWindow.h>
#include <levelfuse/scan/RangeMap.h>

#include <openvdb/openvdb.h>
#include <openvdb/tree/ValueAccessor.h>

namespace levelfuse {

/// The name of the colour grid written beside a level set.
inline constexpr const char* kColourGridName = "Cd";
/// The colour of a surface where no reading with a colour saw it: mid grey,
/// the colour grid's background.
inline constexpr float kUnseenGrey = 0.5f;

/// The colour the maps of `scans` that carry one saw at every voxel of
/// `levelSet`'s narrow band within sqrt(3) voxels of its zero set (the
/// corners of the cells the surface crosses; see above), with the data term's `window` and
/// sigma_x^2 `positionVariance` of Eq. 38. A Vec3fGrid named kColourGridName,
/// GRID_UNKNOWN, the level set's transform, active where some reading gave a
/// colour, background kUnseenGrey, with levelfuse_* metadata. Parallel over
/// leaf nodes and deterministic. Throws std::invalid_argument for a grid that
/// is not a level set, Interrupted if `interrupter` asks to stop.
openvdb::Vec3fGrid::Ptr surfaceColour(const openvdb::FloatGrid& levelSet, const RangeMapSequence& scans,
                                      const DataWindow& window, double positionVariance,
                                      const Interrupter& interrupter = {});

/// Samples a colour grid (surfaceColour's) at world points: interpolated
/// trilinearly between the active voxels around a point; kUnseenGrey where
/// none of the eight is active. One per thread: it keeps its way into the
/// grid's tree between points (the grid must outlive it).
class ColourSampler {
 public:
  explicit ColourSampler(const openvdb::Vec3fGrid& colour) : mColour(colour), mAccess(colour.tree()) {}
  openvdb::Vec3f at(const openvdb::Vec3d& x) const;

 private:
  const openvdb::Vec3fGrid& mColour;
  mutable openvdb::tree::ValueAccessor<const openvdb::Vec3fTree, false> mAccess;
};

/// Gives every vertex of `mesh` the colour of `colour` there (ColourSampler),
/// rounded to bytes (TriangleMesh::rgb).
void paintMesh(TriangleMesh& mesh, const openvdb::Vec3fGrid& colour);

}  // namespace levelfuse
