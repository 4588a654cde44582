// levelfuse: the tiles beside a level set's leaves (see TilesBesideLeaves.h).

#include <levelfuse/levelset/LeafNodeWidth.h>
#include <levelfuse/levelset/TilesBesideLeaves.h>

#include <algorithm>
#include <cstddef>
#include <utility>
#include <vector>

namespace levelfuse {

void setTilesBesideLeaves(openvdb::FloatGrid& grid) {
  openvdb::FloatTree& tree = grid.tree();
  const float width = tree.background();
  std::vector<std::pair<openvdb::Coord, bool>> cells;
  for (auto leaf = tree.cbeginLeaf(); leaf; ++leaf)
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          if (dx == 0 && dy == 0 && dz == 0) continue;
          const openvdb::Int32 w = kLeafNodeWidth;
          const openvdb::Coord cell = leaf->origin().offsetBy(dx * w, dy * w, dz * w);
          if (tree.probeConstLeaf(cell)) continue;
          const auto near = [](int d) { return d > 0 ? kLeafNodeWidth - 1 : 0; };
          const openvdb::Coord voxel = leaf->origin().offsetBy(near(dx), near(dy), near(dz));
          cells.emplace_back(cell, leaf->getValue(voxel) < 0.0f);
        }
  std::stable_sort(cells.begin(), cells.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (std::size_t i = 0; i < cells.size(); ++i)
    if (i == 0 || cells[i].first != cells[i - 1].first)
      tree.addTile(1, cells[i].first, cells[i].second ? -width : width, false);
}

}  // namespace levelfuse
