// levelfuse: .vdb files.

#include <levelfuse/io/AtomicWrite.h>
#include <levelfuse/io/InputError.h>
#include <levelfuse/io/VdbFile.h>

#include <filesystem>
#include <system_error>

namespace levelfuse::io {

void writeVdb(const std::string& path, const openvdb::GridCPtrVec& grids, const openvdb::MetaMap& fileMetadata) {
  openvdb::initialize();
  writeAtomically(path, [&](const std::string& temporary) {
    openvdb::io::File file(temporary);
    file.write(grids, fileMetadata);
    file.close();
  });
}

openvdb::GridPtrVecPtr readVdb(const std::string& path, openvdb::MetaMap::Ptr* fileMetadata) {
  openvdb::initialize();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path, "no such file");
  try {
    openvdb::io::File file(path);
    file.open();
    openvdb::GridPtrVecPtr grids = file.getGrids();
    if (fileMetadata) *fileMetadata = file.getMetadata();
    file.close();
    return grids;
  } catch (const std::exception& e) {
    throw InputError(path, std::string("not a readable .vdb file (") + e.what() + ")");
  }
}

}  // namespace levelfuse::io
