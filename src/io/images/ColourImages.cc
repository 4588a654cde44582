// levelfuse: colour images registered to range maps.

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/InputFile.h>
#include <levelfuse/io/images/ColourImages.h>

#include "ImageSize.h"
#include "PngRead.h"
#include "PngWrite.h"

#include <cstdio>
#include <cstring>
#include <filesystem>

namespace levelfuse::io {

ColourImage readColourPng(const std::string& path, const MemoryBudget& budget) {
  requireInputFile(path);
  std::error_code ec;
  const std::uintmax_t fileBytes = std::filesystem::file_size(path, ec);
  if (ec) throw InputError(path, "cannot be read (" + ec.message() + ")");
  ColourImage image;
  std::vector<std::uint8_t> pixels;
  const std::string problem = detail::readPngPixels(path.c_str(), static_cast<double>(fileBytes),
                                                    detail::PngPixels::kRgb8, detail::kColourImage, budget,
                                                    image.width, image.height, pixels);
  if (!problem.empty()) throw InputError(path, problem);
  image.rgb.resize(pixels.size() / 3);
  std::memcpy(image.rgb.data(), pixels.data(), pixels.size());
  return image;
}

void writeColourPng(OutputSet& outputs, const std::string& path, const ColourImage& image) {
  std::vector<std::uint8_t> bytes(image.rgb.size() * 3);
  std::memcpy(bytes.data(), image.rgb.data(), bytes.size());
  outputs.add(path, [&, bytes](const std::string& temporary) {
    detail::writeRgbPng(temporary, image.width, image.height, bytes);
  });
}

void colourRangeMap(RangeMap& map, ColourImage image, const std::string& path) {
  if (image.width != map.width() || image.height != map.height())
    throw InputError(path, "a colour image of " + std::to_string(image.width) + " x " + std::to_string(image.height) +
                               " pixels for a range map of " + std::to_string(map.width()) + " x " +
                               std::to_string(map.height()) + ": it must be registered to it, pixel for pixel");
  map.setColours(std::move(image.rgb));
}

ColourImage colourImageOf(const RangeMap& map) { return {map.width(), map.height(), map.colours()}; }

}  // namespace levelfuse::io
