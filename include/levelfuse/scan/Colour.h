// levelfuse: the colour a scanner recorded with its readings.
#pragma once

#include <array>
#include <cstdint>

namespace levelfuse {

/// Red, green and blue from 0 to 255, as scanners and cameras record them.
using Rgb8 = std::array<std::uint8_t, 3>;

}  // namespace levelfuse
