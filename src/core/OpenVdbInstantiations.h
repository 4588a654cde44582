// levelfuse: the virtual members of OpenVDB's standard grids and trees, which
// libopenvdb compiles itself, declared so that no levelfuse source compiles
// them again.
//
// A source that makes a grid emits the grid's and its tree's tables of virtual
// functions, and with them every virtual member (their I/O, copies, printing
// and statistics), compiled at -O3 whether it calls them or not: most of the
// compile time of a source that writes several types of grid (docs/BUILD.md,
// "Where the time went"). libopenvdb holds those tables for the standard
// trees, so it has every virtual member they name. Only virtual members are
// declared: of the others libopenvdb exports only those it happens to use.
// Every levelfuse target includes this header first: through its precompiled
// header or by -include (cmake/LevelfuseCompilerSettings.cmake). Not a public
// header.
#pragma once

#include <openvdb/openvdb.h>

#include <iosfwd>

#define LEVELFUSE_OPENVDB_EXTERN_TREE_VIRTUALS(TreeT)                                                            \
  extern template openvdb::tree::Tree<TreeT::RootNodeType>::~Tree();                                          \
  extern template openvdb::tree::TreeBase::Ptr openvdb::tree::Tree<TreeT::RootNodeType>::copy() const;        \
  extern template openvdb::Name openvdb::tree::Tree<TreeT::RootNodeType>::valueType() const;                 \
  extern template const openvdb::Name& openvdb::tree::Tree<TreeT::RootNodeType>::type() const;               \
  extern template bool openvdb::tree::Tree<TreeT::RootNodeType>::evalLeafBoundingBox(openvdb::CoordBBox&) const; \
  extern template bool openvdb::tree::Tree<TreeT::RootNodeType>::evalActiveVoxelBoundingBox(openvdb::CoordBBox&) \
      const;                                                                                                   \
  extern template bool openvdb::tree::Tree<TreeT::RootNodeType>::evalActiveVoxelDim(openvdb::Coord&) const;  \
  extern template bool openvdb::tree::Tree<TreeT::RootNodeType>::evalLeafDim(openvdb::Coord&) const;         \
  extern template void openvdb::tree::Tree<TreeT::RootNodeType>::readTopology(std::istream&, bool);          \
  extern template void openvdb::tree::Tree<TreeT::RootNodeType>::writeTopology(std::ostream&, bool) const;   \
  extern template void openvdb::tree::Tree<TreeT::RootNodeType>::readBuffers(std::istream&, bool);           \
  extern template void openvdb::tree::Tree<TreeT::RootNodeType>::readBuffers(std::istream&,                  \
                                                                             const openvdb::CoordBBox&, bool); \
  extern template void openvdb::tree::Tree<TreeT::RootNodeType>::readNonresidentBuffers() const;             \
  extern template void openvdb::tree::Tree<TreeT::RootNodeType>::writeBuffers(std::ostream&, bool) const;    \
  extern template void openvdb::tree::Tree<TreeT::RootNodeType>::print(std::ostream&, int) const;            \
  extern template openvdb::Index openvdb::tree::Tree<TreeT::RootNodeType>::treeDepth() const;                \
  extern template openvdb::Index32 openvdb::tree::Tree<TreeT::RootNodeType>::leafCount() const;              \
  extern template std::vector<openvdb::Index32> openvdb::tree::Tree<TreeT::RootNodeType>::nodeCount() const; \
  extern template openvdb::Index32 openvdb::tree::Tree<TreeT::RootNodeType>::nonLeafCount() const;           \
  extern template openvdb::Index64 openvdb::tree::Tree<TreeT::RootNodeType>::activeLeafVoxelCount() const;   \
  extern template openvdb::Index64 openvdb::tree::Tree<TreeT::RootNodeType>::inactiveLeafVoxelCount() const; \
  extern template openvdb::Index64 openvdb::tree::Tree<TreeT::RootNodeType>::activeVoxelCount() const;       \
  extern template openvdb::Index64 openvdb::tree::Tree<TreeT::RootNodeType>::inactiveVoxelCount() const;     \
  extern template openvdb::Index64 openvdb::tree::Tree<TreeT::RootNodeType>::activeTileCount() const;        \
  extern template openvdb::Index64 openvdb::tree::Tree<TreeT::RootNodeType>::memUsage() const;               \
  extern template void openvdb::tree::Tree<TreeT::RootNodeType>::clipUnallocatedNodes();                     \
  extern template openvdb::Index32 openvdb::tree::Tree<TreeT::RootNodeType>::unallocatedLeafCount() const;   \
  extern template openvdb::Metadata::Ptr openvdb::tree::Tree<TreeT::RootNodeType>::getBackgroundValue() const; \
  extern template void openvdb::tree::Tree<TreeT::RootNodeType>::getIndexRange(openvdb::CoordBBox&) const;

#define LEVELFUSE_OPENVDB_EXTERN_GRID_VIRTUALS(TreeT)                                                           \
  extern template openvdb::Grid<TreeT>::~Grid();                                                               \
  extern template openvdb::GridBase::Ptr openvdb::Grid<TreeT>::copyGrid();                                     \
  extern template openvdb::GridBase::ConstPtr openvdb::Grid<TreeT>::copyGrid() const;                          \
  extern template openvdb::GridBase::Ptr openvdb::Grid<TreeT>::copyGridWithNewTree() const;                    \
  extern template openvdb::GridBase::ConstPtr openvdb::Grid<TreeT>::copyGridReplacingMetadata(                 \
      const openvdb::MetaMap&) const;                                                                          \
  extern template openvdb::GridBase::ConstPtr openvdb::Grid<TreeT>::copyGridReplacingTransform(                \
      openvdb::math::Transform::Ptr) const;                                                                    \
  extern template openvdb::GridBase::ConstPtr openvdb::Grid<TreeT>::copyGridReplacingMetadataAndTransform(     \
      const openvdb::MetaMap&, openvdb::math::Transform::Ptr) const;                                           \
  extern template openvdb::GridBase::Ptr openvdb::Grid<TreeT>::deepCopyGrid() const;                           \
  extern template openvdb::Name openvdb::Grid<TreeT>::type() const;                                            \
  extern template openvdb::Name openvdb::Grid<TreeT>::valueType() const;                                       \
  extern template bool openvdb::Grid<TreeT>::empty() const;                                                    \
  extern template void openvdb::Grid<TreeT>::clear();                                                          \
  extern template void openvdb::Grid<TreeT>::pruneGrid(float);                                                 \
  extern template void openvdb::Grid<TreeT>::clip(const openvdb::CoordBBox&);                                  \
  extern template openvdb::Index64 openvdb::Grid<TreeT>::activeVoxelCount() const;                             \
  extern template openvdb::CoordBBox openvdb::Grid<TreeT>::evalActiveVoxelBoundingBox() const;                 \
  extern template openvdb::Coord openvdb::Grid<TreeT>::evalActiveVoxelDim() const;                             \
  extern template openvdb::Index64 openvdb::Grid<TreeT>::memUsage() const;                                     \
  extern template openvdb::tree::TreeBase::ConstPtr openvdb::Grid<TreeT>::constBaseTreePtr() const;            \
  extern template bool openvdb::Grid<TreeT>::isTreeUnique() const;                                             \
  extern template void openvdb::Grid<TreeT>::setTree(openvdb::tree::TreeBase::Ptr);                            \
  extern template void openvdb::Grid<TreeT>::newTree();                                                        \
  extern template void openvdb::Grid<TreeT>::readTopology(std::istream&);                                      \
  extern template void openvdb::Grid<TreeT>::writeTopology(std::ostream&) const;                               \
  extern template void openvdb::Grid<TreeT>::readBuffers(std::istream&);                                       \
  extern template void openvdb::Grid<TreeT>::readBuffers(std::istream&, const openvdb::CoordBBox&);            \
  extern template void openvdb::Grid<TreeT>::readNonresidentBuffers() const;                                   \
  extern template void openvdb::Grid<TreeT>::writeBuffers(std::ostream&) const;                                \
  extern template void openvdb::Grid<TreeT>::print(std::ostream&, int) const;

#define LEVELFUSE_OPENVDB_EXTERN_VIRTUALS(TreeT) \
  LEVELFUSE_OPENVDB_EXTERN_TREE_VIRTUALS(TreeT)  \
  LEVELFUSE_OPENVDB_EXTERN_GRID_VIRTUALS(TreeT)

LEVELFUSE_OPENVDB_EXTERN_VIRTUALS(openvdb::MaskTree)
LEVELFUSE_OPENVDB_EXTERN_VIRTUALS(openvdb::BoolTree)
LEVELFUSE_OPENVDB_EXTERN_VIRTUALS(openvdb::Int32Tree)
LEVELFUSE_OPENVDB_EXTERN_VIRTUALS(openvdb::Int64Tree)
LEVELFUSE_OPENVDB_EXTERN_VIRTUALS(openvdb::FloatTree)
LEVELFUSE_OPENVDB_EXTERN_VIRTUALS(openvdb::DoubleTree)
LEVELFUSE_OPENVDB_EXTERN_VIRTUALS(openvdb::Vec3STree)
LEVELFUSE_OPENVDB_EXTERN_VIRTUALS(openvdb::Vec3DTree)
LEVELFUSE_OPENVDB_EXTERN_VIRTUALS(openvdb::Vec3ITree)

#undef LEVELFUSE_OPENVDB_EXTERN_VIRTUALS
#undef LEVELFUSE_OPENVDB_EXTERN_GRID_VIRTUALS
#undef LEVELFUSE_OPENVDB_EXTERN_TREE_VIRTUALS
