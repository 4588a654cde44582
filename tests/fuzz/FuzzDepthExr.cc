// Fuzzes the EXR depth image reader: the header levelfuse reads itself before
// OpenEXR is given the file (and OpenEXR too, where the build has it).

#include "FuzzInput.h"

#include <levelfuse/io/images/DepthImages.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace levelfuse;
  const std::string path = fuzz::writeScratchFile("input.exr", data, size);
  fuzz::expectOnlyInputErrors([&] { io::readDepthExr(path); });
  return 0;
}
