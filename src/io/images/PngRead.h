// levelfuse: the pixels of PNG files, read strictly with libpng (private to
// the image readers).
#pragma once

#include "ImageSize.h"

#include <cstdint>
#include <string>
#include <vector>

namespace levelfuse::io::detail {

/// What a reader takes of a PNG's pixels.
enum class PngPixels {
  kGray16,  ///< one 16-bit channel, in the host's byte order (a depth image); any other PNG is refused
  kRgb8,    ///< red, green and blue bytes; grey, palette, 16-bit and alpha images are converted (a colour image)
};

/// Reads the PNG at `path`, `fileBytes` long, row-major into `pixels` (two
/// bytes a pixel for kGray16, three for kRgb8). Refuses a file that is not a
/// PNG, is truncated or corrupt, declares more pixels than its bytes can hold
/// (deflate shrinks at most 1032:1), or whose size is wrong for `kind`
/// or `budget` (checkImageSize), before the pixels are allocated. Returns an error
/// message, empty on success. Chunks other than the pixels' are skipped unread.
std::string readPngPixels(const char* path, double fileBytes, PngPixels as, const ImageKind& kind,
                          const MemoryBudget& budget, int& width, int& height, std::vector<std::uint8_t>& pixels);

}  // namespace levelfuse::io::detail
