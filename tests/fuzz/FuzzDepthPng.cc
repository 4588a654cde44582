// Fuzzes the PNG readers (libpng underneath): the 16-bit depth image reader
// and the depth frame an image becomes, and the colour image reader, which
// takes every kind of PNG and converts it.

#include "FuzzInput.h"

#include <levelfuse/io/images/ColourImages.h>
#include <levelfuse/io/images/DepthImages.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace levelfuse;
  const std::string path = fuzz::writeScratchFile("input.png", data, size);
  fuzz::expectOnlyInputErrors([&] {
    const io::DepthImage image = io::readDepthPng(path);
    io::depthFrame(image, PinholeProjection{10.0, 10.0, 2.0, 2.0}, openvdb::math::Mat4d::identity(),
                   io::DepthNoise(), "input.png");
  });
  fuzz::expectOnlyInputErrors([&] { io::readColourPng(path); });
  return 0;
}
