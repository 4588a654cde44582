#include "support/TestSupport.h"

#include <levelfuse/levelset/ZeroCrossings.h>

#include <openvdb/tools/LevelSetSphere.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <vector>

namespace levelfuse::test {

openvdb::FloatGrid::Ptr makeSphere(double radius, const openvdb::Vec3d& centre, double dx) {
  return openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(
      static_cast<float>(radius * dx), openvdb::Vec3f(centre), static_cast<float>(dx), 3.0f);
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

int insideComponents(const SparseField& field) {
  // Flood fill over negative band voxels; components that never touch the band
  // cannot exist (every inside region is bounded by the active set).
  const openvdb::FloatGrid& grid = field.grid();
  openvdb::FloatGrid::ConstAccessor acc = grid.getConstAccessor();
  openvdb::MaskGrid::Ptr seen = openvdb::MaskGrid::create();
  openvdb::MaskGrid::Accessor seenAcc = seen->getAccessor();
  int components = 0;
  for (auto it = grid.tree().cbeginValueOn(); it; ++it) {
    if (*it >= 0.0f || seenAcc.isValueOn(it.getCoord())) continue;
    ++components;
    std::vector<openvdb::Coord> stack{it.getCoord()};
    seenAcc.setValueOn(it.getCoord());
    while (!stack.empty()) {
      const openvdb::Coord c = stack.back();
      stack.pop_back();
      static constexpr int kStep[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
      for (const auto& e : kStep) {
        const openvdb::Coord n = c.offsetBy(e[0], e[1], e[2]);
        if (!acc.isValueOn(n) || acc.getValue(n) >= 0.0f || seenAcc.isValueOn(n)) continue;
        seenAcc.setValueOn(n);
        stack.push_back(n);
      }
    }
  }
  return components;
}

std::string sharedData(const std::string& relative) {
  const std::filesystem::path root(LEVELFUSE_SHARED_DATA_DIR);
  if (!std::filesystem::is_directory(root)) return "";
  return (root / relative).string();
}

}  // namespace levelfuse::test
