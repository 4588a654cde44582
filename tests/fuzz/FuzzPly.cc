// Fuzzes the PLY reader (ASCII and binary) and, beyond it, the reading of a
// range-grid scan up to the range map it becomes.

#include "FuzzInput.h"

#include <levelfuse/io/Ply.h>
#include <levelfuse/io/scans/StanfordScans.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace levelfuse;
  const std::string path = fuzz::writeScratchFile("input.ply", data, size);
  fuzz::expectOnlyInputErrors([&] { io::readPly(path); });
  fuzz::expectOnlyInputErrors([&] {
    const io::RangeGridScan scan = io::readRangeGridPly(path);
    io::rangeMapFromScan(scan, openvdb::math::Mat4d::identity(), io::StanfordScanOptions(), "input.ply");
  });
  return 0;
}
