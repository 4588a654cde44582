// levelfuse: colour images registered to range maps: pixel (u, v) of the
// image saw what pixel (u, v) of the map measured (a depth camera's colour
// registered to its depth, a synthetic scan's colours).
#pragma once

#include <levelfuse/io/AtomicWrite.h>
#include <levelfuse/core/MemoryBudget.h>
#include <levelfuse/scan/Colour.h>
#include <levelfuse/scan/RangeMap.h>

#include <string>
#include <vector>

namespace levelfuse::io {

struct ColourImage {
  int width = 0, height = 0;
  std::vector<Rgb8> rgb;  ///< row-major from the top left
};

/// Reads a PNG as 8-bit red, green and blue (grey, palette, 16-bit and alpha
/// images are converted). Throws InputError naming the file and the problem,
/// also for an image that would need more memory than `budget` allows.
ColourImage readColourPng(const std::string& path, const MemoryBudget& budget = {});

/// Writes an 8-bit RGB PNG, as one of a run's outputs (AtomicWrite.h).
void writeColourPng(OutputSet& outputs, const std::string& path, const ColourImage& image);

/// Gives `map` the image's colours (RangeMap::setColours). Throws InputError
/// naming `path`, the image's file, unless the image is the map's size.
void colourRangeMap(RangeMap& map, ColourImage image, const std::string& path);

/// The colours of a map that has them, as an image (for writing beside it).
ColourImage colourImageOf(const RangeMap& map);

}  // namespace levelfuse::io
