// levelfuse: the checks of an image's declared size that every image reader
// makes before it allocates anything (private to the readers).
#pragma once

#include <levelfuse/core/MemoryBudget.h>

namespace levelfuse::io::detail {

/// A problem with an image, as a message; empty if there is none.
using ImageProblem = char[200];

/// What a reader reads an image as.
struct ImageKind {
  const char* name;      ///< for messages: "a depth image"
  int minimumSide;       ///< pixels
  double bytesPerPixel;  ///< held per pixel at most while it is read
};

/// Depth images: at least 2 x 2 (a cell of readings); the samples as stored and the depths.
inline constexpr ImageKind kDepthImage{"a depth image", 2, 8.0};
/// Colour images registered to range maps: the pixels read, and the colours kept.
inline constexpr ImageKind kColourImage{"a colour image", 1, 6.0};

/// Writes into `problem` what is wrong with an image of `width` x `height`
/// pixels read as `kind`: too small, more than a quarter of a billion pixels,
/// or more memory than `budget` allows; leaves it empty if nothing is.
void checkImageSize(double width, double height, const ImageKind& kind, const MemoryBudget& budget,
                    ImageProblem& problem);

}  // namespace levelfuse::io::detail
