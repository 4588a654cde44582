// Shared helpers of levelfuse's tests.
#pragma once

#include <levelfuse/levelset/SlabField.h>
#include <levelfuse/levelset/SparseField.h>

#include <openvdb/openvdb.h>

#include <string>
#include <vector>

namespace levelfuse::test {

/// A narrow-band level set of a sphere of `radius` voxels (voxel size `dx`) at `centre` (world).
openvdb::FloatGrid::Ptr makeSphere(double radius, const openvdb::Vec3d& centre = openvdb::Vec3d(0.0),
                                   double dx = 1.0);

/// `count` points `radius` (world units) from `centre`, in directions drawn at
/// random, uniformly over the sphere, from `seed`.
std::vector<openvdb::Vec3d> pointsOnSphere(const openvdb::Vec3d& centre, double radius, int count, unsigned seed);

/// True if the two grids have the same topology, the same values bit for bit,
/// and the same tiles; otherwise `why` says where they first differ.
bool identical(const openvdb::FloatGrid& a, const openvdb::FloatGrid& b, std::string* why = nullptr);
/// True if OpenVDB writes the two trees (topology and values) as the same
/// bytes: internal nodes and tiles alike, as a .vdb file of them would be.
bool sameTreeBytes(const openvdb::FloatGrid& a, const openvdb::FloatGrid& b);

/// True if `weight` is a weight grid of `levelSet` (recon/SurfaceWeight.h):
/// each of its leaves is a leaf of the band, with the band's active voxels,
/// that some reading faces (a weight above 0), it has no tiles and its
/// background is 0; `facedLeaves`, if given, receives how many leaves it holds.
bool weighsTheBand(const openvdb::FloatGrid& weight, const openvdb::FloatGrid& levelSet,
                   std::size_t* facedLeaves = nullptr);

/// `levelSet` within the x range of `slab` (its tiles split at the slab's
/// faces, background beyond them; Tree::clip), pruned as a level set: what a
/// piece of it (LevelSetPieces.h) must be.
openvdb::FloatGrid::Ptr clippedToSlab(const openvdb::FloatGrid& levelSet, const SlabBounds& slab);

/// How many of `a`'s band voxels `b` puts in another layer (SparseField::layerOf).
std::size_t voxelsInOtherLayers(const SparseField& a, const SparseField& b);

/// Mean and rms deviation of the zero crossings' distances from `centre`.
struct RadiusFit {
  double mean = 0.0;
  double rmsDeviation = 0.0;
  std::size_t points = 0;
};
RadiusFit fitRadius(const openvdb::FloatGrid& grid, const openvdb::Vec3d& centre);


/// Path of a file in ../shared/data, or "" if that folder is absent.
std::string sharedData(const std::string& relative);

}  // namespace levelfuse::test
