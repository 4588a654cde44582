// levelfuse: connected components of a level set's inside.

#include <levelfuse/levelset/Components.h>
#include <levelfuse/levelset/RequireLevelSet.h>
#include <levelfuse/levelset/detail/LeafMaskOps.h>

#include <vector>

namespace levelfuse {

int insideComponents(const openvdb::FloatGrid& grid) {
  requireLevelSet(grid, "insideComponents");
  openvdb::FloatGrid::ConstAccessor acc = grid.getConstAccessor();
  openvdb::MaskTree seen;
  openvdb::tree::ValueAccessor<openvdb::MaskTree> seenAcc(seen);
  int components = 0;
  std::vector<openvdb::Coord> stack;
  for (auto it = grid.tree().cbeginValueOn(); it; ++it) {
    if (*it >= 0.0f || seenAcc.isValueOn(it.getCoord())) continue;
    ++components;
    stack.assign(1, it.getCoord());
    seenAcc.setValueOn(it.getCoord());
    while (!stack.empty()) {
      const openvdb::Coord c = stack.back();
      stack.pop_back();
      for (const auto& e : detail::kFaceOffset) {
        const openvdb::Coord n = c.offsetBy(e[0], e[1], e[2]);
        if (!acc.isValueOn(n) || acc.getValue(n) >= 0.0f || seenAcc.isValueOn(n)) continue;
        seenAcc.setValueOn(n);
        stack.push_back(n);
      }
    }
  }
  return components;
}

}  // namespace levelfuse
