// levelfuse: leaf records of the sparse field and their neighbour links.

#include <levelfuse/levelset/detail/SparseFieldState.h>

namespace levelfuse::detail {

namespace {
constexpr int kLeafDim = static_cast<int>(FloatLeaf::DIM);
}

void LeafTable::build(FloatTree& tree) {
  mRecords.clear();
  mFree.clear();
  mIndex.clear();
  for (auto it = tree.beginLeaf(); it; ++it) add(it.getLeaf());
}

std::int32_t LeafTable::add(FloatLeaf* leaf) {
  std::int32_t index;
  if (!mFree.empty()) {
    index = mFree.back();
    mFree.pop_back();
    mRecords[index] = LeafRecord{};
  } else {
    index = static_cast<std::int32_t>(mRecords.size());
    mRecords.emplace_back();
  }
  LeafRecord& record = mRecords[index];
  record.leaf = leaf;
  record.origin = leaf->origin();
  mIndex.emplace(record.origin, index);
  for (int dx = -1; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dz = -1; dz <= 1; ++dz) {
        const int slot = neighbourSlot(dx, dy, dz);
        if (slot == kSelfSlot) {
          record.neighbour[slot] = index;
          continue;
        }
        const std::int32_t n = find(record.origin.offsetBy(dx * kLeafDim, dy * kLeafDim, dz * kLeafDim));
        record.neighbour[slot] = n;
        if (n >= 0) mRecords[n].neighbour[neighbourSlot(-dx, -dy, -dz)] = index;
      }
  return index;
}

void LeafTable::remove(std::int32_t index) {
  LeafRecord& record = mRecords[index];
  for (int dx = -1; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dz = -1; dz <= 1; ++dz) {
        const int slot = neighbourSlot(dx, dy, dz);
        const std::int32_t n = record.neighbour[slot];
        if (slot != kSelfSlot && n >= 0) mRecords[n].neighbour[neighbourSlot(-dx, -dy, -dz)] = -1;
      }
  mIndex.erase(record.origin);
  record = LeafRecord{};
  mFree.push_back(index);
}

std::int32_t LeafTable::find(const openvdb::Coord& origin) const {
  const auto it = mIndex.find(origin);
  return it == mIndex.end() ? -1 : it->second;
}

std::size_t LeafTable::memoryBytes() const {
  return mRecords.capacity() * sizeof(LeafRecord) + mFree.capacity() * sizeof(std::int32_t) +
         mIndex.bucket_count() * sizeof(void*) +
         mIndex.size() * (sizeof(openvdb::Coord) + sizeof(std::int32_t) + 2 * sizeof(void*));
}

}  // namespace levelfuse::detail
