// Fuzzes the PTX reader: the input as a .ptx file, read scan by scan and each
// scan binned into a spherical range map (loadScans: readPtxScans, the steps
// of its grid, the binning).

#include "FuzzInput.h"

#include <levelfuse/io/scans/Scans.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace levelfuse;
  const std::string path = fuzz::writeScratchFile("input.ptx", data, size);
  fuzz::expectOnlyInputErrors([&] { io::loadScans(path); });
  return 0;
}
