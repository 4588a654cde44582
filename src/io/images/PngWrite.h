// levelfuse: 8-bit RGB PNG files, written with libpng (private to the writers
// of previews and colour images).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace levelfuse::io::detail {

/// Writes `rgb` (three bytes a pixel, row-major from the top left) as an 8-bit
/// RGB PNG at `path`; throws std::runtime_error saying what failed.
void writeRgbPng(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb);

}  // namespace levelfuse::io::detail
