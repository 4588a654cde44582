// .vdb files: valid files of every supported kind read; truncated and
// corrupted ones end in an InputError that names the file, never in a crash
// or an allocation that a small file cannot justify.

#include "LargestAllocation.h"
#include "support/Files.h"
#include "support/InputErrors.h"

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/vdb/VdbFile.h>

#include <openvdb/io/File.h>
#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>

#include <gtest/gtest.h>

#include <fstream>
#include <initializer_list>
#include <iterator>
#include <string>
#include <vector>

namespace levelfuse::io {
namespace {

/// No reading of a small bad file may allocate more than this at once.
constexpr std::size_t kMaxAllocation = 16 << 20;

/// A small float level set: a few active voxels in one leaf, an inactive
/// value of the other sign, a transform of 0.5.
openvdb::FloatGrid::Ptr smallLevelSet(const std::string& name = "ls") {
  openvdb::initialize();
  auto grid = openvdb::FloatGrid::create(3.0f);
  grid->setName(name);
  grid->setGridClass(openvdb::GRID_LEVEL_SET);
  grid->setTransform(openvdb::math::Transform::createLinearTransform(0.5));
  auto accessor = grid->getAccessor();
  for (int i = 0; i < 6; ++i) accessor.setValue(openvdb::Coord(i, i % 3, 1), 0.25f * float(i) - 1.0f);
  accessor.setValueOff(openvdb::Coord(7, 7, 7), -3.0f);
  accessor.setValue(openvdb::Coord(-300, 40, 9), 0.5f);  // a second root child
  return grid;
}

/// A level set of a plane across 8 x 8 leaves: enough leaves that OpenVDB
/// compresses its delayed-load metadata (padded to 128 bytes).
openvdb::FloatGrid::Ptr planeLevelSet() {
  auto grid = smallLevelSet("plane");
  auto accessor = grid->getAccessor();
  for (int x = 0; x < 64; ++x)
    for (int y = 0; y < 64; ++y) accessor.setValue(openvdb::Coord(x, y, 0), 0.01f * float(x - y));
  return grid;
}

void writeWithOpenVdb(const std::string& path, const openvdb::GridPtrVec& grids, std::uint32_t compression) {
  openvdb::io::File file(path);
  file.setCompression(compression);
  file.write(grids);
  file.close();
}

std::vector<char> bytesOf(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeBytes(const std::string& path, const std::vector<char>& bytes, std::size_t size) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(size));
}

template <typename GridT>
void expectSameVoxels(const GridT& expected, const openvdb::GridBase::Ptr& read) {
  const auto grid = openvdb::GridBase::grid<GridT>(read);
  ASSERT_TRUE(grid) << read->type();
  EXPECT_EQ(grid->getName(), expected.getName());
  EXPECT_EQ(grid->activeVoxelCount(), expected.activeVoxelCount());
  EXPECT_EQ(grid->voxelSize(), expected.voxelSize());
  for (auto it = expected.cbeginValueOn(); it; ++it) EXPECT_EQ(grid->tree().getValue(it.getCoord()), *it);
}

class VdbFiles : public ::testing::Test {
 protected:
  test::TempDir mDir;
};

TEST_F(VdbFiles, FilesOfEveryCompressionStillRead) {
  const auto grid = planeLevelSet();
  namespace vio = openvdb::io;
  for (const std::uint32_t compression : std::initializer_list<std::uint32_t>{vio::COMPRESS_NONE, vio::COMPRESS_ACTIVE_MASK, vio::COMPRESS_ZIP, vio::COMPRESS_ZIP | vio::COMPRESS_ACTIVE_MASK,
        vio::COMPRESS_BLOSC, vio::COMPRESS_BLOSC | vio::COMPRESS_ACTIVE_MASK}) {
    SCOPED_TRACE(vio::compressionToString(compression));
    const std::string path = mDir.path("c.vdb");
    writeWithOpenVdb(path, {grid}, compression);
    const openvdb::GridPtrVecPtr grids = readVdb(path);
    ASSERT_EQ(grids->size(), 1u);
    expectSameVoxels(*grid, (*grids)[0]);
  }
}

TEST_F(VdbFiles, FilesWrittenByLevelfuseStillRead) {
  const auto grid = planeLevelSet();
  openvdb::MetaMap metadata;
  metadata.insertMeta("creator", openvdb::StringMetadata("levelfuse test"));
  metadata.insertMeta("flag", openvdb::BoolMetadata(true));
  writeVdb(mDir.path("l.vdb"), {grid}, metadata);
  openvdb::MetaMap::Ptr readMetadata;
  const openvdb::GridPtrVecPtr grids = readVdb(mDir.path("l.vdb"), &readMetadata);
  ASSERT_EQ(grids->size(), 1u);
  expectSameVoxels(*grid, (*grids)[0]);
  ASSERT_TRUE(readMetadata);
  EXPECT_EQ(readMetadata->metaValue<std::string>("creator"), "levelfuse test");
}

TEST_F(VdbFiles, HalfFloatsManyGridTypesInstancesAndStreamsStillRead) {
  auto half = smallLevelSet("half");
  half->setSaveFloatAsHalf(true);
  auto vectors = openvdb::Vec3SGrid::create();
  vectors->setName("v");
  vectors->tree().setValue(openvdb::Coord(1, 2, 3), openvdb::Vec3s(1, 2, 3));
  auto halfVectors = openvdb::Vec3DGrid::create();
  halfVectors->setName("hv");
  halfVectors->setSaveFloatAsHalf(true);
  halfVectors->tree().setValue(openvdb::Coord(-9, 2, 3), openvdb::Vec3d(0.5, 2, 3));
  auto doubles = openvdb::DoubleGrid::create(1.0);
  doubles->setName("d");
  doubles->tree().setValue(openvdb::Coord(-100, 5, 3), 2.5);
  doubles->tree().addTile(1, openvdb::Coord(0, 0, 0), 4.0, true);
  auto integers = openvdb::Int32Grid::create();
  integers->setName("i");
  integers->tree().setValue(openvdb::Coord(4000, 5, 3), 7);
  auto longs = openvdb::Int64Grid::create();
  longs->setName("l");
  longs->tree().setValue(openvdb::Coord(4, 5, 3), 1ll << 40);
  auto indices = openvdb::Vec3IGrid::create();
  indices->setName("vi");
  indices->tree().setValue(openvdb::Coord(4, 5, 3), openvdb::Vec3i(1, -2, 3));
  const auto level = smallLevelSet("shared");
  const auto instance = level->copyGrid();  // shares the tree: written as an instance
  instance->setName("instance");
  const openvdb::GridPtrVec grids{half, vectors, halfVectors, doubles, integers, longs, indices, level, instance};

  for (const bool stream : {false, true}) {
    SCOPED_TRACE(stream ? "io::Stream" : "io::File");
    const std::string path = mDir.path("many.vdb");
    if (stream) {
      std::ofstream out(path, std::ios::binary | std::ios::trunc);
      openvdb::io::Stream(out).write(grids);
    } else {
      writeWithOpenVdb(path, grids, openvdb::io::COMPRESS_BLOSC | openvdb::io::COMPRESS_ACTIVE_MASK);
    }
    const openvdb::GridPtrVecPtr read = readVdb(path);
    ASSERT_EQ(read->size(), grids.size());
    const auto find = [&](const std::string& name) {
      for (const auto& grid : *read)
        if (grid->getName() == name) return grid;
      return openvdb::GridBase::Ptr();
    };
    expectSameVoxels(*vectors, find("v"));
    expectSameVoxels(*doubles, find("d"));
    expectSameVoxels(*integers, find("i"));
    expectSameVoxels(*longs, find("l"));
    expectSameVoxels(*indices, find("vi"));
    expectSameVoxels(*level, find("shared"));
    ASSERT_TRUE(find("instance"));
    EXPECT_EQ(find("instance")->activeVoxelCount(), level->activeVoxelCount());
    ASSERT_TRUE(find("half"));
    EXPECT_EQ(find("half")->activeVoxelCount(), half->activeVoxelCount());
    ASSERT_TRUE(find("hv"));
    EXPECT_EQ(find("hv")->activeVoxelCount(), 1);
  }
}

TEST_F(VdbFiles, GridTypesLevelfuseDoesNotReadAreNamedWithThoseItDoes) {
  auto mask = openvdb::BoolGrid::create();
  mask->setName("mask");
  mask->tree().setValue(openvdb::Coord(1, 2, 3), true);
  writeWithOpenVdb(mDir.path("b.vdb"), {mask}, openvdb::io::COMPRESS_BLOSC);
  test::expectInputError([&] { readVdb(mDir.path("b.vdb")); }, mDir.path("b.vdb"),
                         "grid 'mask' is of type 'Tree_bool_5_4_3'; levelfuse reads grids of float, double, int32, "
                         "int64, vec3s, vec3d and vec3i values");
}

TEST_F(VdbFiles, TransformsLevelfuseCannotUseAreRefused) {
  auto frustum = smallLevelSet();
  frustum->setTransform(openvdb::math::Transform::createFrustumTransform(
      openvdb::BBoxd(openvdb::Vec3d(0), openvdb::Vec3d(10)), 0.5, 2.0, 1.0));
  writeWithOpenVdb(mDir.path("f.vdb"), {frustum}, openvdb::io::COMPRESS_BLOSC);
  test::expectInputError([&] { readVdb(mDir.path("f.vdb")); }, mDir.path("f.vdb"),
                         "a transform of type 'NonlinearFrustumMap'; levelfuse reads the linear maps");

  auto flat = smallLevelSet();
  flat->setTransform(openvdb::math::Transform::Ptr(new openvdb::math::Transform(
      openvdb::math::MapBase::Ptr(new openvdb::math::TranslationMap(openvdb::Vec3d(1, 2, 3))))));
  writeWithOpenVdb(mDir.path("t.vdb"), {flat}, openvdb::io::COMPRESS_BLOSC);
  EXPECT_NO_THROW(readVdb(mDir.path("t.vdb")));
}

TEST_F(VdbFiles, GridsThatNeedMoreMemoryThanTheBudgetAreRefused) {
  writeVdb(mDir.path("l.vdb"), {smallLevelSet()});
  test::expectInputError([&] { readVdb(mDir.path("l.vdb"), nullptr, MemoryBudget(64 << 10)); }, mDir.path("l.vdb"),
                         "the grids in the file needs about");
  EXPECT_NO_THROW(readVdb(mDir.path("l.vdb")));  // the machine's budget holds them
}

/// Offsets in a file of `size` bytes: all of the first `head` bytes and the
/// last `tail`, every `step`-th between (where masks and values repeat).
std::vector<std::size_t> sampleOffsets(std::size_t size, std::size_t head, std::size_t tail, std::size_t step) {
  std::vector<std::size_t> offsets;
  for (std::size_t offset = 0; offset < size; offset += (offset < head || offset + tail >= size) ? 1 : step)
    offsets.push_back(offset);
  return offsets;
}

/// Writes prefixes of `bytes` to `path` and expects each to be refused.
void expectTruncationsRefused(const std::string& path, const std::vector<char>& bytes,
                              const std::vector<std::size_t>& sizes) {
  for (const std::size_t size : sizes) {
    writeBytes(path, bytes, size);
    test::LargestAllocation largest;
    test::expectInputError([&] { readVdb(path); }, path, "");
    ASSERT_LE(largest.bytes(), kMaxAllocation) << "a file cut to " << size << " bytes";
    if (::testing::Test::HasFailure()) {
      ADD_FAILURE() << "a file cut to " << size << " of " << bytes.size() << " bytes";
      return;
    }
  }
}

TEST_F(VdbFiles, TruncationsAreRefusedWithAShortMessage) {
  namespace vio = openvdb::io;
  for (const std::uint32_t compression : std::initializer_list<std::uint32_t>{vio::COMPRESS_BLOSC | vio::COMPRESS_ACTIVE_MASK, vio::COMPRESS_ZIP | vio::COMPRESS_ACTIVE_MASK}) {
    SCOPED_TRACE(vio::compressionToString(compression));
    writeWithOpenVdb(mDir.path("whole.vdb"), {smallLevelSet()}, compression);
    const std::vector<char> bytes = bytesOf(mDir.path("whole.vdb"));
    expectTruncationsRefused(mDir.path("cut.vdb"), bytes, sampleOffsets(bytes.size(), 400, 1500, 61));
  }
  writeWithOpenVdb(mDir.path("whole.vdb"), {smallLevelSet()}, vio::COMPRESS_NONE);
  const std::vector<char> raw = bytesOf(mDir.path("whole.vdb"));
  expectTruncationsRefused(mDir.path("cut.vdb"), raw, sampleOffsets(raw.size(), 400, 400, 997));

  const std::vector<char> bytes = bytesOf(mDir.path("whole.vdb"));
  writeBytes(mDir.path("cut.vdb"), bytes, bytes.size() / 2);
  try {
    readVdb(mDir.path("cut.vdb"));
    ADD_FAILURE() << "read a truncated file";
  } catch (const InputError& e) {
    EXPECT_LE(std::string(e.what()).size(), 300u) << e.what();
    EXPECT_NE(std::string(e.what()).find("truncated?"), std::string::npos) << e.what();
  }
}

TEST_F(VdbFiles, CorruptedBytesReadOrAreRefusedNeverWorse) {
  namespace vio = openvdb::io;
  const std::string path = mDir.path("bad.vdb");
  for (const std::uint32_t compression : std::initializer_list<std::uint32_t>{vio::COMPRESS_BLOSC | vio::COMPRESS_ACTIVE_MASK, vio::COMPRESS_ZIP | vio::COMPRESS_ACTIVE_MASK,
        vio::COMPRESS_ACTIVE_MASK}) {
    SCOPED_TRACE(vio::compressionToString(compression));
    auto half = smallLevelSet("half");
    half->setSaveFloatAsHalf(true);
    writeWithOpenVdb(mDir.path("whole.vdb"), {smallLevelSet(), half}, compression);
    const std::vector<char> bytes = bytesOf(mDir.path("whole.vdb"));
    std::size_t refused = 0, offsets = 0;
    for (const std::size_t offset : sampleOffsets(bytes.size(), 400, 800, 97)) {
      for (const unsigned char value : {0xff, 0x80}) {
        std::vector<char> corrupt = bytes;
        corrupt[offset] = static_cast<char>(value == 0xff ? ~corrupt[offset] : value);
        writeBytes(path, corrupt, corrupt.size());
        test::LargestAllocation largest;
        try {
          readVdb(path);
        } catch (const InputError& e) {
          ++refused;
          EXPECT_EQ(e.file(), path);
        }
        ASSERT_LE(largest.bytes(), kMaxAllocation) << "byte " << offset << " set to " << int(value);
      }
      ++offsets;
    }
    EXPECT_GT(refused, offsets / 2);
  }
}

}  // namespace
}  // namespace levelfuse::io
