// levelfuse: the colour the scans saw on a surface.

#include <levelfuse/core/Parallel.h>
#include <levelfuse/levelset/RequireLevelSet.h>
#include <levelfuse/levelset/VoxelNormals.h>
#include <levelfuse/scan/SurfaceColour.h>

#include "LeavesReached.h"
#include "ReadingWeight.h"
#include "TrilinearCorners.h"

#include <openvdb/tools/Prune.h>
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

/// The colour tree: the voxels of the level set's band within
/// kColouredHalfWidth voxels of its zero set, at `grey`; leaves without one
/// are pruned.
std::shared_ptr<ColourTree> colouredVoxels(const openvdb::FloatGrid& levelSet, const Vec3f& grey) {
  openvdb::MaskTree near(levelSet.tree(), false, openvdb::TopologyCopy());  // a bit a voxel while it is sorted out
  const float halfWidth = static_cast<float>(kColouredHalfWidth * levelSet.voxelSize()[0]);
  openvdb::tree::LeafManager<openvdb::MaskTree> leaves(near);
  leaves.foreach([&](openvdb::MaskTree::LeafNodeType& leaf, std::size_t) {
    const openvdb::FloatTree::LeafNodeType* phi = levelSet.tree().probeConstLeaf(leaf.origin());
    for (auto it = leaf.beginValueOn(); it; ++it)
      if (!phi || std::fabs(phi->getValue(it.pos())) > halfWidth) leaf.setValueOff(it.pos());
  });
  openvdb::tools::pruneInactive(near);
  return std::make_shared<ColourTree>(near, grey, Vec3f(0.0f), openvdb::TopologyCopy());
}
/// The steps of a leaf's voxels that have a normal, in order.
using LeafSurfaceSteps = std::vector<SurfaceStep>;

/// The surface steps of every active voxel of the leaves, found once for all
/// the maps (parallel over the leaves).
std::vector<LeafSurfaceSteps> surfaceSteps(const openvdb::FloatGrid& levelSet,
                                           const openvdb::tree::LeafManager<ColourTree>& leaves,
                                           const ParallelInterrupt& interrupt) {
  std::vector<LeafSurfaceSteps> steps(leaves.leafCount());
  const VoxelNormals normals(levelSet);
  parallelFor(steps.size(), 1, [&](std::size_t begin, std::size_t end) {
    openvdb::FloatGrid::ConstAccessor phi = levelSet.getConstAccessor();
    for (std::size_t i = begin; i < end && !interrupt.stop(); ++i)
      for (auto it = leaves.leaf(i).cbeginValueOn(); it; ++it) {
        const Coord ijk = it.getCoord();
        Vec3d normal;
        if (!normals.at(phi, ijk, normal)) continue;
        steps[i].push_back({it.pos(), Vec3f(normal)});
      }
  });
  interrupt.throwIfStopped();
  return steps;
}

/// Adds one map's colours, weighted, to the sums of every voxel of a leaf
/// whose nearest surface point it sees from outside.
struct AddMapColoursOp {
  const openvdb::FloatGrid* levelSet;
  const std::vector<LeafSurfaceSteps>* steps;  ///< per leaf of the colour tree's LeafManager
  const RangeMap* map;
  const detail::UsableSpans* spans;  ///< the map's, when culling
  const DataWindow* window;
  double positionVariance;
  bool cull;            ///< cubes of leaves the map's readings cannot reach are skipped
  double cullReach;     ///< the window's reach plus the band's half-width
  openvdb::FloatTree* weights;
  const ParallelInterrupt* interrupt;

  void operator()(ColourTree::LeafNodeType& sums, std::size_t leaf) const {
    if (interrupt->stop()) return;
    const double h = levelSet->voxelSize()[0];
    const std::uint8_t cubes = cull ? detail::leafCubesMayBeReached(*spans, sums.origin(), h, cullReach) : 0xFF;
    if (cubes == 0) return;
    openvdb::FloatTree::LeafNodeType* weightLeaf = weights->probeLeaf(sums.origin());
    const openvdb::FloatTree::LeafNodeType* phi = levelSet->tree().probeConstLeaf(sums.origin());
    const openvdb::math::Mat4d& toMap = map->worldToMap();
    const openvdb::math::Mat4d& toWorld = map->mapToWorld();
    const double reach = window->reach();
    RangeMap::LocalSample s;
    for (const SurfaceStep& step : (*steps)[leaf]) {
      if (!(cubes & (1u << detail::cubeOfOffset(step.offset)))) continue;
      const Vec3d toSurface = -Vec3d(step.normal) * static_cast<double>(phi->getValue(step.offset));
      const Vec3d nearest = levelSet->indexToWorld(sums.offsetToGlobalCoord(step.offset)) + toSurface;
      const Vec3d p = toMap.transform(nearest);
      if (!map->sampleLocal(p, reach, s)) continue;
      if (!(toWorld.transform3x3(s.lineOfSight).dot(Vec3d(step.normal)) < 0.0)) continue;  // Eq. 37
      const double w = (*window)(s.D);
      if (w == 0.0) continue;
      Vec3f rgb;
      if (!map->colourAt(p, rgb)) continue;
      const double weight = detail::readingWeight(w, s, positionVariance);  // Eq. 38
      sums.setValueOnly(step.offset, sums.getValue(step.offset) + rgb * static_cast<float>(weight));
      weightLeaf->setValueOnly(step.offset, weightLeaf->getValue(step.offset) + static_cast<float>(weight));
    }
  }
};

/// Each voxel's weighted sum divided by its weight; voxels no colour reached
/// are left inactive, at the background.
struct MeanColourOp {
  const openvdb::FloatTree* weights;
  void operator()(ColourTree::LeafNodeType& sums, std::size_t) const {
    const openvdb::FloatTree::LeafNodeType* weightLeaf = weights->probeConstLeaf(sums.origin());
    for (auto it = sums.beginValueOn(); it; ++it) {
      const float w = weightLeaf->getValue(it.pos());
      if (w > 0.0f)
        it.setValue(*it / w);
      else
        sums.setValueOff(it.pos(), Vec3f(kUnseenGrey));
    }
  }
};

}  // namespace

openvdb::Vec3fGrid::Ptr surfaceColour(const openvdb::FloatGrid& levelSet, const RangeMapSequence& scans,
                                      const DataWindow& window, double positionVariance,
                                      const Interrupter& interrupter) {
  requireLevelSet(levelSet, "surfaceColour");
  const Vec3f grey(kUnseenGrey);
  auto colour = openvdb::Vec3fGrid::create(grey);
  colour->setTransform(levelSet.transform().copy());
  colour->setTree(colouredVoxels(levelSet, grey));
  colour->setName(kColourGridName);
  colour->setGridClass(openvdb::GRID_UNKNOWN);
  openvdb::FloatTree weights(colour->tree(), 0.0f, openvdb::TopologyCopy());

  const ParallelInterrupt interrupt(interrupter);
  openvdb::tree::LeafManager<ColourTree> leaves(colour->tree());
  const double bandHalfWidth = std::abs(static_cast<double>(levelSet.background()));
  const std::vector<LeafSurfaceSteps> steps = surfaceSteps(levelSet, leaves, interrupt);
  AddMapColoursOp add{&levelSet, &steps, nullptr, nullptr, &window, positionVariance,
                      centredOnMultiples(levelSet.transform()), window.reach() + bandHalfWidth, &weights,
                      &interrupt};
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
  leaves.foreach(MeanColourOp{&weights});

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
