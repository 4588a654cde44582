// Fuzzes the plain-text camera files: intrinsics (3 x 3) and poses (4 x 4).

#include "FuzzInput.h"

#include <levelfuse/io/images/DepthImages.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace levelfuse;
  const std::string path = fuzz::writeScratchFile("input.txt", data, size);
  fuzz::expectOnlyInputErrors([&] { io::readIntrinsics(path); });
  fuzz::expectOnlyInputErrors([&] { io::readPose(path); });
  return 0;
}
