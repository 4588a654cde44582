// Fuzzes the .vdb reader and what `levelfuse info` and `levelfuse mesh` do
// with the grids it returns.

#include "FuzzInput.h"

#include <levelfuse/io/vdb/VdbFile.h>
#include <levelfuse/levelset/Components.h>
#include <levelfuse/levelset/Mesh.h>
#include <levelfuse/levelset/RequireLevelSet.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace levelfuse;
  const std::string path = fuzz::writeScratchFile("input.vdb", data, size);
  fuzz::expectOnlyInputErrors([&] {
    openvdb::MetaMap::Ptr fileMetadata;
    const openvdb::GridPtrVecPtr grids = io::readVdb(path, &fileMetadata);
    for (const openvdb::GridBase::Ptr& grid : *grids) {
      grid->activeVoxelCount();
      grid->memUsage();
      grid->evalActiveVoxelBoundingBox();
      const auto levelSet = openvdb::GridBase::grid<openvdb::FloatGrid>(grid);
      if (!levelSet || !levelSetProblem(*levelSet).empty()) continue;  // as info and mesh skip them
      insideComponents(*levelSet);
      meshFromLevelSet(*levelSet, 0.0);
    }
  });
  return 0;
}
