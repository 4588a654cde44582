// levelfuse: the active voxels of a float grid whose values pass a test, as a
// mask tree (the band near a zero set, the voxels a weight says were seen).
#pragma once

#include <openvdb/openvdb.h>
#include <openvdb/tools/Prune.h>
#include <openvdb/tree/LeafManager.h>

namespace levelfuse::detail {

/// A tree of MaskTreeT's type (a MaskTree, a BoolTree) active at the active
/// voxels of `values` where keep(value) holds, its leaves without one pruned;
/// parallel over the leaves.
template <typename MaskTreeT, typename Keep>
MaskTreeT voxelsWhere(const openvdb::FloatTree& values, const Keep& keep) {
  MaskTreeT mask(values, false, openvdb::TopologyCopy());
  openvdb::tree::LeafManager<MaskTreeT> leaves(mask);
  leaves.foreach([&](typename MaskTreeT::LeafNodeType& leaf, std::size_t) {
    const openvdb::FloatTree::LeafNodeType* source = values.probeConstLeaf(leaf.origin());
    for (auto it = leaf.beginValueOn(); it; ++it)
      if (!source || !keep(source->getValue(it.pos()))) leaf.setValueOff(it.pos());
  });
  openvdb::tools::pruneInactive(mask);
  return mask;
}

}  // namespace levelfuse::detail
