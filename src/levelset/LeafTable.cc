// levelfuse: leaf records of the sparse field and their neighbour links.

#include <levelfuse/levelset/detail/LeafNeighbourhood.h>
#include <levelfuse/levelset/LeafNodeWidth.h>

namespace levelfuse::detail {

namespace {
const float kEmptyValues[FloatLeaf::SIZE] = {};
const std::uint64_t kEmptyMaskWords[FloatLeaf::SIZE / 64] = {};
}  // namespace

const float* emptyLeafValues() { return kEmptyValues; }
const std::uint64_t* emptyLeafMaskWords() { return kEmptyMaskWords; }

namespace {

/// Address of the voxel (i, j, k) + d, with i, j, k in [0, 8) and d in {-1, 0, 1}^3.
NeighbourAddress addressOf(int i, int j, int k, const int d[3]) {
  const int c[3] = {i + d[0], j + d[1], k + d[2]};
  int slot = 0, offset = 0;
  for (int a = 0; a < 3; ++a) {
    const int side = c[a] < 0 ? 0 : (c[a] > 7 ? 2 : 1);
    slot = slot * 3 + side;
    offset = offset * 8 + (c[a] & 7);
  }
  return NeighbourAddress{static_cast<std::uint16_t>(offset), static_cast<std::uint8_t>(slot)};
}

/// True if Stencil's points 1 to 6 are the face neighbours in Face order.
constexpr bool stencilFacesInFaceOrder() {
  for (int f = 0; f < kFaceCount; ++f)
    for (int axis = 0; axis < 3; ++axis)
      if (Stencil::kOffset[1 + f][axis] != kFaceOffset[f][axis]) return false;
  return true;
}
static_assert(stencilFacesInFaceOrder(), "Stencil's face points and kFaceOffset must agree");

struct NeighbourTables {
  NeighbourAddress face[FloatLeaf::SIZE][kFaceCount];
  NeighbourAddress stencil[FloatLeaf::SIZE][Stencil::kSize];
  NeighbourTables() {
    for (unsigned o = 0; o < FloatLeaf::SIZE; ++o) {
      const openvdb::Coord ijk = FloatLeaf::offsetToLocalCoord(o);
      const int i = ijk.x(), j = ijk.y(), k = ijk.z();
      for (int f = 0; f < kFaceCount; ++f) face[o][f] = addressOf(i, j, k, kFaceOffset[f]);
      for (int p = 0; p < Stencil::kSize; ++p) stencil[o][p] = addressOf(i, j, k, Stencil::kOffset[p]);
    }
  }
};

const NeighbourTables& tables() {
  static const NeighbourTables instance;
  return instance;
}

}  // namespace

const NeighbourAddress* faceNeighbourTable() { return &tables().face[0][0]; }
const NeighbourAddress* stencilNeighbourTable() { return &tables().stencil[0][0]; }

void LeafTable::build(FloatTree& tree) {
  mRecords.clear();
  mFree.clear();
  mIndex.clear();
  // Room for the band to grow by a quarter before the records move: grown
  // record by record, the table would double as it filled, and hold up to
  // twice its records and three times while moving.
  const std::size_t leaves = tree.leafCount();
  mRecords.reserve(leaves + leaves / 4);
  mIndex.reserve(leaves + leaves / 4);
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
  record.values = leaf->buffer().data();
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
        const std::int32_t n =
            find(record.origin.offsetBy(dx * kLeafNodeWidth, dy * kLeafNodeWidth, dz * kLeafNodeWidth));
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
