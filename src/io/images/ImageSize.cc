// levelfuse: the checks of an image's declared size.

#include "ImageSize.h"

#include <levelfuse/io/MemoryBudget.h>

#include <cstdio>

namespace levelfuse::io::detail {

namespace {

constexpr double kMaxPixels = 1 << 28;  // a quarter of a billion: a gigabyte of floats
const char* const kImageTooLargeAdvice = "crop or downsample the image, or use a machine with more memory";

}  // namespace

void checkImageSize(double width, double height, const ImageKind& kind, const MemoryBudget& memory,
                    ImageProblem& problem) {
  const double bytes = width * height * kind.bytesPerPixel, budget = static_cast<double>(memory.bytes());
  const double side = kind.minimumSide;
  if (!(width >= side) || !(height >= side))
    std::snprintf(problem, sizeof(problem), "the image has %.12g x %.12g pixels; %s needs at least %d x %d", width,
                  height, kind.name, kind.minimumSide, kind.minimumSide);
  else if (!(width * height <= kMaxPixels))
    std::snprintf(problem, sizeof(problem), "the header declares %.12g x %.12g pixels: too large for %s", width,
                  height, kind.name);
  else if (bytes > budget)
    std::snprintf(problem, sizeof(problem), "an image of %.12g x %.12g pixels needs about %s of memory, more than "
                  "the %s levelfuse may use: %s", width, height, describeBytes(bytes).c_str(),
                  describeBytes(budget).c_str(), kImageTooLargeAdvice);
}

}  // namespace levelfuse::io::detail
