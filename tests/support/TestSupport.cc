#include "support/TestSupport.h"

#include <levelfuse/levelset/ZeroCrossings.h>

#include <levelfuse/core/Parallel.h>

#include <openvdb/tools/LevelSetSphere.h>
#include <openvdb/tools/Prune.h>
#include <tbb/global_control.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>
#include <random>
#include <sstream>
#include <vector>

namespace levelfuse::test {

#if defined(LEVELFUSE_THREAD_SANITIZER)
namespace {
/// TSan builds: TBB runs on one thread (levelfuse's own loops still run on
/// several std::threads, see core/Parallel.h), so OpenVDB's internal TBB tasks,
/// whose synchronisation TSan cannot see, raise no false reports.
class SerialTbbEnvironment : public ::testing::Environment {
 public:
  void SetUp() override {
    mLimit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, 1);
  }
  void TearDown() override { mLimit.reset(); }

 private:
  std::unique_ptr<tbb::global_control> mLimit;
};
const auto* const kSerialTbb = ::testing::AddGlobalTestEnvironment(new SerialTbbEnvironment);
}  // namespace
#endif

openvdb::FloatGrid::Ptr makeSphere(double radius, const openvdb::Vec3d& centre, double dx) {
  return openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(
      static_cast<float>(radius * dx), openvdb::Vec3f(centre), static_cast<float>(dx), 3.0f);
}

std::vector<openvdb::Vec3d> pointsOnSphere(const openvdb::Vec3d& centre, double radius, int count, unsigned seed) {
  std::mt19937 random(seed);
  std::normal_distribution<double> normal;
  std::vector<openvdb::Vec3d> points;
  for (int i = 0; i < count; ++i) {
    openvdb::Vec3d direction(normal(random), normal(random), normal(random));
    direction.normalize();
    points.push_back(centre + direction * radius);
  }
  return points;
}

std::size_t voxelsInOtherLayers(const SparseField& a, const SparseField& b) {
  std::size_t differ = 0;
  for (auto it = a.grid().tree().cbeginValueOn(); it; ++it)
    differ += a.layerOf(it.getCoord()) != b.layerOf(it.getCoord());
  return differ;
}

bool identical(const openvdb::FloatGrid& a, const openvdb::FloatGrid& b, std::string* why) {
  const auto fail = [&](const std::string& s) {
    if (why) *why = s;
    return false;
  };
  if (a.tree().leafCount() != b.tree().leafCount()) return fail("different leaf counts");
  if (a.tree().activeVoxelCount() != b.tree().activeVoxelCount()) return fail("different active voxel counts");
  openvdb::FloatGrid::ConstAccessor bacc = b.getConstAccessor();
  for (auto leaf = a.tree().cbeginLeaf(); leaf; ++leaf) {
    const auto* other = bacc.probeConstLeaf(leaf->origin());
    if (!other) return fail("leaf missing in the second grid");
    if (leaf->getValueMask() != other->getValueMask()) return fail("different active masks");
    for (openvdb::Index o = 0; o < leaf->SIZE; ++o) {
      const float x = leaf->getValue(o), y = other->getValue(o);
      if (std::memcmp(&x, &y, sizeof(float)) != 0) {
        std::ostringstream s;
        s << "values differ at " << leaf->offsetToGlobalCoord(o) << ": " << x << " vs " << y;
        return fail(s.str());
      }
    }
  }
  for (auto it = a.tree().cbeginValueAll(); it; ++it) {
    if (it.isVoxelValue()) continue;
    if (bacc.getValue(it.getCoord()) != *it) return fail("tiles differ");
  }
  return true;
}

namespace {
std::string treeBytes(const openvdb::FloatGrid& grid) {
  std::ostringstream out(std::ios_base::binary);
  grid.tree().writeTopology(out);
  grid.tree().writeBuffers(out);
  return out.str();
}
}  // namespace

bool sameTreeBytes(const openvdb::FloatGrid& a, const openvdb::FloatGrid& b) { return treeBytes(a) == treeBytes(b); }

bool weighsTheBand(const openvdb::FloatGrid& weight, const openvdb::FloatGrid& levelSet, std::size_t* facedLeaves) {
  std::size_t leaves = 0;
  for (auto leaf = weight.tree().cbeginLeaf(); leaf; ++leaf) {
    const openvdb::FloatTree::LeafNodeType* band = levelSet.tree().probeConstLeaf(leaf->origin());
    if (!band || leaf->getValueMask() != band->getValueMask()) return false;
    bool faced = false;
    for (auto v = leaf->cbeginValueOn(); v; ++v) faced = faced || *v > 0.0f;
    if (!faced) return false;
    ++leaves;
  }
  if (facedLeaves) *facedLeaves = leaves;
  return weight.tree().activeTileCount() == 0 && weight.background() == 0.0f;
}

openvdb::FloatGrid::Ptr clippedToSlab(const openvdb::FloatGrid& levelSet, const SlabBounds& slab) {
  // Far beyond any grid's voxels, yet the box's extent fits an Int32.
  constexpr openvdb::Int32 far = 1 << 29;
  const openvdb::CoordBBox box(openvdb::Coord(std::max(slab.begin, -far), -far, -far),
                               openvdb::Coord(std::min(slab.end, far) - 1, far, far));
  openvdb::FloatGrid::Ptr clipped = levelSet.deepCopy();
  clipped->tree().clip(box);
  openvdb::tools::pruneLevelSet(clipped->tree());
  return clipped;
}

RadiusFit fitRadius(const openvdb::FloatGrid& grid, const openvdb::Vec3d& centre) {
  const std::vector<openvdb::Vec3d> points = zeroCrossings(grid);
  RadiusFit fit;
  fit.points = points.size();
  if (points.empty()) return fit;
  double sum = 0.0, sumSq = 0.0;
  for (const auto& p : points) {
    const double r = (p - centre).length();
    sum += r;
    sumSq += r * r;
  }
  fit.mean = sum / points.size();
  fit.rmsDeviation = std::sqrt(std::max(0.0, sumSq / points.size() - fit.mean * fit.mean));
  return fit;
}

std::string sharedData(const std::string& relative) {
  const std::filesystem::path root(LEVELFUSE_SHARED_DATA_DIR);
  if (!std::filesystem::is_directory(root)) return "";
  return (root / relative).string();
}

}  // namespace levelfuse::test
