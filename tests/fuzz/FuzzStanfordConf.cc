// Fuzzes the Stanford .conf reader; a valid scan.ply lies beside the input,
// so placements that survive the reader are loaded as range maps too.

#include "FuzzInput.h"
#include "ScanFixtures.h"

#include <levelfuse/io/scans/StanfordScans.h>

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  levelfuse::fuzz::writeScanFixtures();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace levelfuse;
  const std::string path = fuzz::writeScratchFile("input.conf", data, size);
  fuzz::expectOnlyInputErrors([&] { io::loadStanfordScans(path); });
  return 0;
}
