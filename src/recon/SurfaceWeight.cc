// levelfuse: the data weight on a level set's narrow band.

#include <levelfuse/levelset/RequireLevelSet.h>
#include <levelfuse/levelset/VoxelNormals.h>
#include <levelfuse/recon/SurfaceWeight.h>

#include <openvdb/tree/LeafManager.h>

#include <algorithm>
#include <memory>

namespace levelfuse {

namespace {

using openvdb::Coord;
using openvdb::Vec3d;

/// Per active voxel of the band: the facing readings (Eq. 37) at the voxel for
/// the level set's outward normal there.
template <typename Data>
struct FacingWeightOp {
  const openvdb::FloatGrid* levelSet;
  const Data* data;
  VoxelNormals normals;
  const ParallelInterrupt* interrupt;

  void operator()(openvdb::FloatTree::LeafNodeType& leaf, std::size_t) const {
    if (interrupt->stop()) return;
    openvdb::FloatGrid::ConstAccessor phi = levelSet->getConstAccessor();
    for (auto it = leaf.beginValueOn(); it; ++it) {
      const Coord ijk = it.getCoord();
      Vec3d normal;
      float value = 0.0f;
      if (normals.at(phi, ijk, normal))
        value = static_cast<float>(data->facingTerms(levelSet->indexToWorld(ijk), normal).readings);
      it.setValue(value);
    }
  }
};

template <typename Data>
openvdb::FloatGrid::Ptr facingWeight(const openvdb::FloatGrid& levelSet, const Data& data,
                                     const Interrupter& interrupter) {
  requireLevelSet(levelSet, "surfaceWeight");
  auto weight = openvdb::FloatGrid::create(0.0f);
  weight->setTransform(levelSet.transform().copy());
  weight->setTree(std::make_shared<openvdb::FloatTree>(levelSet.tree(), 0.0f, openvdb::TopologyCopy()));
  weight->setName(kWeightGridName);
  weight->setGridClass(openvdb::GRID_UNKNOWN);

  const ParallelInterrupt interrupt(interrupter);
  FacingWeightOp<Data> op{&levelSet, &data, VoxelNormals(levelSet), &interrupt};
  openvdb::tree::LeafManager<openvdb::FloatTree> leaves(weight->tree());
  leaves.foreach(op);
  interrupt.throwIfStopped();

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
