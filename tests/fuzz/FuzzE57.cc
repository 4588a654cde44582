// Fuzzes the E57 reader: the input as an .e57 file, its pages, XML and
// compressed vectors read scan by scan and each scan made a spherical range
// map (loadScans: readE57Scans, the station's grid or the binning of its
// points). Fuzzer builds skip the pages' checksums, so that mutations reach
// the XML and the packets.

#include "FuzzInput.h"

#include <levelfuse/io/scans/Scans.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace levelfuse;
  const std::string path = fuzz::writeScratchFile("input.e57", data, size);
  fuzz::expectOnlyInputErrors([&] { io::loadScans(path); });
  return 0;
}
