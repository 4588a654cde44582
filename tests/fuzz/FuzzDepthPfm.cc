// Fuzzes the PFM depth image reader and the depth frame an image becomes.

#include "FuzzInput.h"

#include <levelfuse/io/images/DepthImages.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace levelfuse;
  const std::string path = fuzz::writeScratchFile("input.pfm", data, size);
  fuzz::expectOnlyInputErrors([&] {
    const io::DepthImage image = io::readDepthPfm(path);
    io::depthFrame(image, PinholeProjection{10.0, 10.0, 2.0, 2.0}, openvdb::math::Mat4d::identity(),
                   io::DepthNoise(), "input.pfm");
  });
  return 0;
}
