// levelfuse: colour images registered to range maps.

#include <levelfuse/io/ColourImages.h>
#include <levelfuse/io/InputError.h>
#include <levelfuse/io/InputFile.h>
#include <levelfuse/io/MemoryBudget.h>

#include "PngRead.h"
#include "PngWrite.h"

#include <cstdio>
#include <cstring>
#include <filesystem>

namespace levelfuse::io {

namespace {

/// A colour image is as large as the range map it colours: at most a
/// quarter of a billion pixels, and within the memory levelfuse may use.
void checkColourImageSize(double width, double height, detail::PngProblem& problem) {
  const double bytes = width * height * 6.0;  // the pixels read, and the colours kept
  if (!(width >= 1.0) || !(height >= 1.0))
    std::snprintf(problem, sizeof(problem), "the image has %.12g x %.12g pixels", width, height);
  else if (!(width * height <= double(1 << 28)))
    std::snprintf(problem, sizeof(problem), "the header declares %.12g x %.12g pixels: too large for a colour image",
                  width, height);
  else if (bytes > static_cast<double>(memoryBudget()))
    std::snprintf(problem, sizeof(problem), "an image of %.12g x %.12g pixels needs about %s of memory, more than "
                  "levelfuse may use", width, height, describeBytes(bytes).c_str());
}

}  // namespace

ColourImage readColourPng(const std::string& path) {
  requireInputFile(path);
  std::error_code ec;
  const std::uintmax_t fileBytes = std::filesystem::file_size(path, ec);
  if (ec) throw InputError(path, "cannot be read (" + ec.message() + ")");
  ColourImage image;
  std::vector<std::uint8_t> pixels;
  const std::string problem = detail::readPngPixels(path.c_str(), static_cast<double>(fileBytes),
                                                    detail::PngPixels::kRgb8, checkColourImageSize, image.width,
                                                    image.height, pixels);
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
