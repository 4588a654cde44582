// Fuzzes the JSON scan manifest; valid scans, depth images and camera files
// lie beside the input (see ScanFixtures.h) for its entries to refer to.

#include "FuzzInput.h"
#include "ScanFixtures.h"

#include <levelfuse/io/scans/Manifest.h>

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  levelfuse::fuzz::writeScanFixtures();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace levelfuse;
  const std::string path = fuzz::writeScratchFile("input.json", data, size);
  fuzz::expectOnlyInputErrors([&] { io::loadManifest(path); });
  return 0;
}
