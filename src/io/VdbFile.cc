// levelfuse: .vdb files.

#include <levelfuse/io/VdbFile.h>

#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <system_error>
#include <unistd.h>

namespace levelfuse::io {

namespace fs = std::filesystem;

void writeVdb(const std::string& path, const openvdb::GridCPtrVec& grids, const openvdb::MetaMap& fileMetadata) {
  openvdb::initialize();
  const fs::path target(path);
  const fs::path temporary =
      target.parent_path() / ("." + target.filename().string() + ".tmp" + std::to_string(::getpid()));
  try {
    openvdb::io::File file(temporary.string());
    file.write(grids, fileMetadata);
    file.close();
  } catch (const std::exception& e) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw std::runtime_error("cannot write '" + path + "': " + e.what());
  }
  std::error_code ec;
  fs::rename(temporary, target, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw std::runtime_error("cannot write '" + path + "': " + ec.message());
  }
}

openvdb::GridPtrVecPtr readVdb(const std::string& path, openvdb::MetaMap::Ptr* fileMetadata) {
  openvdb::initialize();
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) throw std::runtime_error("cannot read '" + path + "': no such file");
  try {
    openvdb::io::File file(path);
    file.open();
    openvdb::GridPtrVecPtr grids = file.getGrids();
    if (fileMetadata) *fileMetadata = file.getMetadata();
    file.close();
    return grids;
  } catch (const std::exception& e) {
    throw std::runtime_error("cannot read '" + path + "': " + e.what());
  }
}

}  // namespace levelfuse::io
