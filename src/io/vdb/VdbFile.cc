// levelfuse: .vdb files.

#include <levelfuse/io/AtomicWrite.h>
#include <levelfuse/io/InputError.h>
#include <levelfuse/io/InputFile.h>
#include <levelfuse/io/vdb/VdbFile.h>

#include "VdbValidation.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <vector>

namespace levelfuse::io {
namespace {

// The header of a .vdb file (OpenVDB file format 222 and later): magic number
// (8 bytes), file version, library major and minor version (4 bytes each), a
// flag for grid offsets (1 byte), then a 36-character UUID.
constexpr std::size_t kUuidOffset = 21;
constexpr std::size_t kUuidLength = 36;

/// Replaces the random UUID that OpenVDB writes into the header of the .vdb file
/// at `path` with one made from the file's content, so that the same grids make
/// the same bytes. OpenVDB uses the UUID only to tell whether two files are the
/// same, which a content-derived one tells better. Files whose header is not the
/// expected one are left as written.
void stampContentUuid(const std::string& path) {
  std::fstream file(path, std::ios::in | std::ios::out | std::ios::binary);
  if (!file) throw std::runtime_error(path + ": cannot be reopened to finish the header");
  std::array<unsigned char, kUuidOffset + kUuidLength> header{};
  file.read(reinterpret_cast<char*>(header.data()), static_cast<std::streamsize>(header.size()));
  if (file.gcount() != static_cast<std::streamsize>(header.size())) return;
  const std::uint32_t magic = header[0] | header[1] << 8 | header[2] << 16 | static_cast<std::uint32_t>(header[3]) << 24;
  const std::uint32_t version = header[8] | header[9] << 8 | header[10] << 16 | static_cast<std::uint32_t>(header[11]) << 24;
  if (magic != 0x56444220u || version < 222u || header[kUuidOffset + 8] != '-') return;

  // Two 64-bit FNV-1a hashes with different offsets over everything after the UUID.
  std::uint64_t a = 0xcbf29ce484222325ull, b = 0x84222325cbf29ce4ull;
  std::vector<char> chunk(1 << 20);
  while (file.read(chunk.data(), static_cast<std::streamsize>(chunk.size())) || file.gcount() > 0) {
    for (std::streamsize i = 0; i < file.gcount(); ++i) {
      const auto byte = static_cast<unsigned char>(chunk[static_cast<std::size_t>(i)]);
      a = (a ^ byte) * 0x100000001b3ull;
      b = (b ^ byte) * 0x100000001b3ull;
    }
  }
  file.clear();
  // Version 8 (custom) UUID, RFC 9562 variant.
  char uuid[kUuidLength + 1];
  std::snprintf(uuid, sizeof uuid, "%08x-%04x-8%03x-%04x-%012llx", static_cast<unsigned>(a >> 32),
                static_cast<unsigned>((a >> 16) & 0xffffu), static_cast<unsigned>(a & 0xfffu),
                static_cast<unsigned>(0x8000u | ((b >> 48) & 0x3fffu)),
                static_cast<unsigned long long>(b & 0xffffffffffffull));
  file.seekp(static_cast<std::streamoff>(kUuidOffset));
  file.write(uuid, static_cast<std::streamsize>(kUuidLength));
  if (!file.flush()) throw std::runtime_error(path + ": cannot finish the header");
}

/// Writes grids as openvdb::io::File does (a seekable stream, with grid
/// offsets), but to a stream that is checked: File::write does not look at
/// its stream, so a full disk left a truncated file that looked written.
class CheckedVdbWriter : public openvdb::io::Archive {
 public:
  void writeFile(const std::string& path, const openvdb::GridCPtrVec& grids, const openvdb::MetaMap& metadata) const {
    std::ofstream out(path, std::ios::out | std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot open a temporary file beside it");
    Archive::write(out, grids, /*seekable=*/true, metadata);
    closeChecked(out);
  }
};

/// Throws InputError unless every grid's voxels have a finite, positive size:
/// OpenVDB reads a scale of zero or infinity without complaint.
void requireUsableTransforms(const std::string& path, const openvdb::GridPtrVec& grids) {
  for (const openvdb::GridBase::Ptr& grid : grids) {
    const openvdb::Vec3d size = grid->voxelSize();
    for (int axis = 0; axis < 3; ++axis)
      if (!std::isfinite(size[axis]) || size[axis] <= 0.0)
        throw InputError(path, "grid " + quote(grid->getName()) + " has voxels of size " + size.str() +
                                   ": not a usable transform");
  }
}

}  // namespace

void writeVdb(OutputSet& outputs, const std::string& path, const openvdb::GridCPtrVec& grids,
              const openvdb::MetaMap& fileMetadata) {
  openvdb::initialize();
  outputs.add(path, [&](const std::string& temporary) {
    CheckedVdbWriter().writeFile(temporary, grids, fileMetadata);
    stampContentUuid(temporary);
  });
}

void writeVdb(const std::string& path, const openvdb::GridCPtrVec& grids, const openvdb::MetaMap& fileMetadata) {
  OutputSet outputs;
  writeVdb(outputs, path, grids, fileMetadata);
  outputs.commit();
}

openvdb::GridPtrVecPtr readVdb(const std::string& path, openvdb::MetaMap::Ptr* fileMetadata,
                               const MemoryBudget& budget) {
  openvdb::initialize();
  requireInputFile(path);
  detail::validateVdbFile(path, budget);
  openvdb::GridPtrVecPtr grids;
  try {
    openvdb::io::File file(path);
    // Read now, not later from a mapping of the file: a file that changes
    // after its check could not then fail here, where its name is known.
    file.open(/*delayLoad=*/false);
    grids = file.getGrids();
    if (fileMetadata) *fileMetadata = file.getMetadata();
    file.close();
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(path, "not a readable .vdb file (" + excerpt(e.what()) + ")");
  }
  requireUsableTransforms(path, *grids);
  return grids;
}

}  // namespace levelfuse::io
