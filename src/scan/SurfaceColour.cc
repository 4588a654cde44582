// levelfuse: the colour the scans saw on a surface.

#include <levelfuse/core/FreedMemory.h>
#include <levelfuse/core/Parallel.h>
#include <levelfuse/levelset/RequireLevelSet.h>
#include <levelfuse/levelset/VoxelNormals.h>
#include <levelfuse/levelset/detail/VoxelsWhere.h>
#include <levelfuse/scan/SurfaceColour.h>

#include "LeavesReached.h"
#include "ReadingWeight.h"
#include "TrilinearCorners.h"

#include <openvdb/tree/LeafManager.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

namespace levelfuse {

namespace {

using openvdb::Coord;
using openvdb::Vec3d;
using openvdb::Vec3f;
using ColourTree = openvdb::Vec3fTree;

/// True when the grid's voxel centres lie at whole multiples of its voxel
/// size along the world axes, as the leaf culling of the data term assumes.
bool centredOnMultiples(const openvdb::math::Transform& transform) {
  const double h = transform.voxelSize()[0];
  return transform.isLinear() && transform.hasUniformScale() &&
         (transform.indexToWorld(Coord(1, 2, 3)) - Vec3d(h, 2 * h, 3 * h)).length() <= 1e-9 * h &&
         transform.indexToWorld(Coord(0)).length() <= 1e-9 * h;
}

/// Voxels farther than this from the zero set (in voxels) take no colour:
/// the corners of every cell the surface passes through lie within
/// sqrt(3) voxels of it, and a colour is sampled at the surface alone
/// (ColourSampler).
constexpr double kColouredHalfWidth = 1.7320508075688772;

/// Where a voxel's colour is looked for: its nearest surface point y = x -
/// phi N, and the outward normal N there (world).
struct SurfaceStep {
  openvdb::Index offset;  ///< the voxel in its leaf
  Vec3f normal;
};

/// What colouring holds of a leaf, made when a map's readings may first
/// reach it: the steps of its voxels that have a normal, in order, and,
/// once a reading gave one of them a colour, the weighted sums of each
/// step's voxel. Leaves no map reaches (most of a scene's unseen faces) hold
/// nothing.
struct LeafColouring {
  std::vector<SurfaceStep> steps;
  std::vector<Vec3f> colour;  ///< per step, empty until a reading gives one a colour
  std::vector<float> weight;  ///< per step, as `colour`
};

/// The voxels of the level set's band within kColouredHalfWidth voxels of
/// its zero set, a bit each; leaves without one are pruned.
openvdb::MaskTree colouredVoxels(const openvdb::FloatGrid& levelSet) {
  const float halfWidth = static_cast<float>(kColouredHalfWidth * levelSet.voxelSize()[0]);
  return detail::voxelsWhere<openvdb::MaskTree>(levelSet.tree(), [&](float phi) { return std::fabs(phi) <= halfWidth; });
}

/// The steps of a leaf's coloured voxels.
std::vector<SurfaceStep> surfaceSteps(const openvdb::MaskTree::LeafNodeType& leaf, const VoxelNormals& normals,
                                      openvdb::FloatGrid::ConstAccessor& phi) {
  std::vector<SurfaceStep> steps;
  for (auto it = leaf.cbeginValueOn(); it; ++it) {
    Vec3d normal;
    if (normals.at(phi, it.getCoord(), normal)) steps.push_back({it.pos(), Vec3f(normal)});
  }
  steps.shrink_to_fit();
  return steps;
}

/// Adds one map's colours, weighted, to the sums of every voxel of a leaf
/// whose nearest surface point it sees from outside.
struct AddMapColoursOp {
  const openvdb::FloatGrid* levelSet;
  const VoxelNormals* normals;
  std::vector<std::unique_ptr<LeafColouring>>* colouring;  ///< per leaf of the mask's LeafManager
  const RangeMap* map;
  const detail::UsableSpans* spans;  ///< the map's, when culling
  const DataWindow* window;
  double positionVariance;
  bool cull;            ///< cubes of leaves the map's readings cannot reach are skipped
  double cullReach;     ///< the window's reach plus the band's half-width
  const ParallelInterrupt* interrupt;

  void operator()(const openvdb::MaskTree::LeafNodeType& mask, std::size_t leaf) const {
    if (interrupt->stop()) return;
    const double h = levelSet->voxelSize()[0];
    const std::uint8_t cubes = cull ? detail::leafCubesMayBeReached(*spans, mask.origin(), h, cullReach) : 0xFF;
    if (cubes == 0) return;
    std::unique_ptr<LeafColouring>& held = (*colouring)[leaf];
    if (!held) {
      openvdb::FloatGrid::ConstAccessor phiAccess = levelSet->getConstAccessor();
      held = std::make_unique<LeafColouring>();
      held->steps = surfaceSteps(mask, *normals, phiAccess);
    }
    const openvdb::FloatTree::LeafNodeType* phi = levelSet->tree().probeConstLeaf(mask.origin());
    const openvdb::math::Mat4d& toMap = map->worldToMap();
    const openvdb::math::Mat4d& toWorld = map->mapToWorld();
    const double reach = window->reach();
    RangeMap::LocalSample s;
    for (std::size_t k = 0; k < held->steps.size(); ++k) {
      const SurfaceStep& step = held->steps[k];
      if (!(cubes & (1u << detail::cubeOfOffset(step.offset)))) continue;
      const Vec3d toSurface = -Vec3d(step.normal) * static_cast<double>(phi->getValue(step.offset));
      const Vec3d nearest = levelSet->indexToWorld(mask.offsetToGlobalCoord(step.offset)) + toSurface;
      const Vec3d p = toMap.transform(nearest);
      if (!map->sampleLocal(p, reach, s)) continue;
      if (!(toWorld.transform3x3(s.lineOfSight).dot(Vec3d(step.normal)) < 0.0)) continue;  // Eq. 37
      const double w = (*window)(s.D);
      if (w == 0.0) continue;
      Vec3f rgb;
      if (!map->colourAt(p, rgb)) continue;
      const double weight = detail::readingWeight(w, s, positionVariance);  // Eq. 38
      if (held->weight.empty()) {
        held->colour.assign(held->steps.size(), Vec3f(0.0f));
        held->weight.assign(held->steps.size(), 0.0f);
      }
      held->colour[k] += rgb * static_cast<float>(weight);
      held->weight[k] += static_cast<float>(weight);
    }
  }
};

/// The colour tree: each voxel some reading coloured, at its weighted mean
/// colour; background `grey`.
std::shared_ptr<ColourTree> meanColours(const openvdb::tree::LeafManager<const openvdb::MaskTree>& leaves,
                                        const std::vector<std::unique_ptr<LeafColouring>>& colouring,
                                        const Vec3f& grey) {
  auto tree = std::make_shared<ColourTree>(grey);
  for (std::size_t i = 0; i < colouring.size(); ++i) {
    if (!colouring[i] || colouring[i]->weight.empty()) continue;
    const LeafColouring& sums = *colouring[i];
    auto* leaf = new ColourTree::LeafNodeType(leaves.leaf(i).origin(), grey, false);
    for (std::size_t k = 0; k < sums.steps.size(); ++k)
      if (sums.weight[k] > 0.0f) leaf->setValueOn(sums.steps[k].offset, sums.colour[k] / sums.weight[k]);
    tree->addLeaf(leaf);
  }
  return tree;
}

}  // namespace

openvdb::Vec3fGrid::Ptr surfaceColour(const openvdb::FloatGrid& levelSet, const RangeMapSequence& scans,
                                      const DataWindow& window, double positionVariance,
                                      const Interrupter& interrupter) {
  requireLevelSet(levelSet, "surfaceColour");
  const openvdb::MaskTree near = colouredVoxels(levelSet);
  openvdb::tree::LeafManager<const openvdb::MaskTree> leaves(near);
  std::vector<std::unique_ptr<LeafColouring>> colouring(leaves.leafCount());
  const VoxelNormals normals(levelSet);
  const ParallelInterrupt interrupt(interrupter);
  const double bandHalfWidth = std::abs(static_cast<double>(levelSet.background()));
  AddMapColoursOp add{&levelSet, &normals, &colouring, nullptr, nullptr, &window, positionVariance,
                      centredOnMultiples(levelSet.transform()), window.reach() + bandHalfWidth, &interrupt};
  scans([&](const RangeMap& map) {
    checkInterrupter(interrupter);
    if (!map.hasColours()) return;
    std::optional<detail::UsableSpans> spans;
    if (add.cull) spans.emplace(map);
    add.map = &map;
    add.spans = spans ? &*spans : nullptr;
    leaves.foreach(add);
    interrupt.throwIfStopped();
  });

  const Vec3f grey(kUnseenGrey);
  auto colour = openvdb::Vec3fGrid::create(grey);
  colour->setTransform(levelSet.transform().copy());
  colour->setTree(meanColours(leaves, colouring, grey));
  std::vector<std::unique_ptr<LeafColouring>>().swap(colouring);
  returnFreedMemory();  // the sums, built on the worker threads' heaps
  colour->setName(kColourGridName);
  colour->setGridClass(openvdb::GRID_UNKNOWN);
  colour->insertMeta("levelfuse_surface", openvdb::StringMetadata(levelSet.getName()));
  colour->insertMeta("levelfuse_units", openvdb::StringMetadata("red, green, blue from 0 to 1"));
  colour->insertMeta("levelfuse_description",
                     openvdb::StringMetadata("the colour the scans saw at the surface point nearest each voxel, "
                                             "weighted as their readings are in the data term (Eqs. 8-9, 13, 37, "
                                             "38); inactive, mid grey, where no reading with a colour saw it"));
  return colour;
}

Vec3f ColourSampler::at(const Vec3d& x) const {
  const detail::TrilinearCorners around = detail::trilinearCorners(mColour.worldToIndex(x));
  Vec3d sum(0.0);
  double weight = 0.0;
  for (int k = 0; k < 8; ++k) {
    Vec3f value;
    if (!mAccess.probeValue(around.ijk[k], value)) continue;  // inactive: no colour there
    sum += Vec3d(value) * around.t[k];
    weight += around.t[k];
  }
  return weight > 0.0 ? Vec3f(sum / weight) : Vec3f(kUnseenGrey);
}

void paintMesh(TriangleMesh& mesh, const openvdb::Vec3fGrid& colour) {
  mesh.rgb.resize(mesh.xyz.size());
  parallelFor(mesh.vertexCount(), 4096, [&](std::size_t begin, std::size_t end) {
    const ColourSampler sample(colour);
    for (std::size_t v = begin; v < end; ++v) {
      const Vec3f c = sample.at(Vec3d(mesh.xyz[3 * v], mesh.xyz[3 * v + 1], mesh.xyz[3 * v + 2]));
      for (int k = 0; k < 3; ++k)
        mesh.rgb[3 * v + k] = static_cast<std::uint8_t>(std::lround(std::clamp(c[k], 0.0f, 1.0f) * 255.0f));
    }
  });
}

}  // namespace levelfuse
