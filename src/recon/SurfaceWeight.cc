// levelfuse: the data weight on a level set's narrow band.

#include <levelfuse/levelset/RequireLevelSet.h>
#include <levelfuse/levelset/VoxelNormals.h>
#include <levelfuse/recon/SurfaceWeight.h>
#include <levelfuse/scan/DataTermGrids.h>

#include <openvdb/tree/LeafManager.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

namespace levelfuse {

namespace {

using openvdb::Coord;
using openvdb::Vec3d;

/// Per leaf of the band: the facing readings (Eq. 37) at the surface point
/// nearest each active voxel for the level set's outward normal there, as a leaf with the band leaf's
/// active voxels, or none when no reading faces any of them (most of a
/// scene's unseen faces, which space carving closed).
template <typename Data>
struct FacingWeightOp {
  const openvdb::FloatGrid* levelSet;
  const Data* data;
  VoxelNormals normals;
  std::vector<std::unique_ptr<openvdb::FloatTree::LeafNodeType>>* weighed;  ///< per leaf of the band
  const ParallelInterrupt* interrupt;

  void operator()(const openvdb::FloatTree::LeafNodeType& band, std::size_t n) const {
    if (interrupt->stop()) return;
    if (!mayHaveTermsIn(*data, nearestPointsBox(band))) return;  // no reading faces it: no leaf
    openvdb::FloatGrid::ConstAccessor phi = levelSet->getConstAccessor();
    auto&& terms = samplerOf(*data);  // one leaf's voxels, one task
    auto leaf = std::make_unique<openvdb::FloatTree::LeafNodeType>(band, 0.0f, openvdb::TopologyCopy());
    bool faced = false;
    for (auto it = leaf->beginValueOn(); it; ++it) {
      const Coord ijk = it.getCoord();
      Vec3d normal;
      if (!normals.at(phi, ijk, normal)) continue;
      // At the surface point nearest the voxel, y = x - phi N: a voxel off a
      // surface seen at a grazing angle lies outside the readings' windows
      // along their rays, however well they saw the surface.
      const Vec3d nearest = levelSet->indexToWorld(ijk) - normal * static_cast<double>(band.getValue(it.pos()));
      const auto value = static_cast<float>(terms.facingTerms(nearest, normal).readings);
      it.setValue(value);
      faced = faced || value > 0.0f;
    }
    if (faced) (*weighed)[n] = std::move(leaf);
  }

  /// The world box that holds the surface points nearest the leaf's active
  /// voxels: each lies |phi| from its voxel along the unit normal.
  openvdb::BBoxd nearestPointsBox(const openvdb::FloatTree::LeafNodeType& band) const {
    float reach = 0.0f;
    for (auto it = band.cbeginValueOn(); it; ++it) reach = std::max(reach, std::fabs(*it));
    openvdb::BBoxd box = levelSet->transform().indexToWorld(band.getNodeBoundingBox());
    box.expand(static_cast<double>(reach) * (1.0 + 1e-6));
    return box;
  }
};

template <typename Data>
openvdb::FloatGrid::Ptr facingWeight(const openvdb::FloatGrid& levelSet, const Data& data,
                                     const Interrupter& interrupter) {
  requireLevelSet(levelSet, "surfaceWeight");
  const ParallelInterrupt interrupt(interrupter);
  openvdb::tree::LeafManager<const openvdb::FloatTree> band(levelSet.tree());
  std::vector<std::unique_ptr<openvdb::FloatTree::LeafNodeType>> weighed(band.leafCount());
  band.foreach(FacingWeightOp<Data>{&levelSet, &data, VoxelNormals(levelSet), &weighed, &interrupt});
  interrupt.throwIfStopped();

  auto weight = openvdb::FloatGrid::create(0.0f);
  weight->setTransform(levelSet.transform().copy());
  for (auto& leaf : weighed)
    if (leaf) weight->tree().addLeaf(leaf.release());
  weight->setName(kWeightGridName);
  weight->setGridClass(openvdb::GRID_UNKNOWN);

  weight->insertMeta("levelfuse_surface", openvdb::StringMetadata(levelSet.getName()));
  weight->insertMeta("levelfuse_units", openvdb::StringMetadata("readings"));
  weight->insertMeta("levelfuse_description",
                     openvdb::StringMetadata("how many readings face the surface (Eq. 37; the sum of their windows, "
                                             "one whose window is 1 counting one): 0 where no scan observed it"));
  weight->insertMeta("levelfuse_observed_weight", openvdb::DoubleMetadata(kObservedWeight));
  return weight;
}

}  // namespace

openvdb::FloatGrid::Ptr surfaceWeight(const openvdb::FloatGrid& levelSet, const ForceField& data,
                                      const Interrupter& interrupter) {
  return facingWeight(levelSet, data, interrupter);
}

openvdb::FloatGrid::Ptr surfaceWeight(const openvdb::FloatGrid& levelSet, const DataTermGrids& data,
                                      const Interrupter& interrupter) {
  return facingWeight(levelSet, data, interrupter);
}

bool scansOfAScene(const std::vector<RangeMap>& maps) {
  return !maps.empty() &&
         std::all_of(maps.begin(), maps.end(), [](const RangeMap& m) { return m.ofAScene(); });
}

}  // namespace levelfuse
