// levelfuse: one scan of a PTX file (the format is described in PtxScans.h):
// its station and where the file holds it.
#pragma once

#include <levelfuse/io/scans/StationGrid.h>
#include <levelfuse/scan/Colour.h>

#include <cstdint>

namespace levelfuse::io {

/// A point's colour as a seven-field PTX line gives it: r, g, b from 0 to 255.
using PtxColour = Rgb8;

/// One scan of a PTX file: a station (its points in the scanner's own
/// frame, intensities always) and where the file holds it.
struct PtxScan : StationGrid {
  int index = 0;      ///< 1 for the file's first scan
  std::int64_t firstLine = 0;  ///< the line of its column count
  std::int64_t lastLine = 0;   ///< the line of its last point
};

}  // namespace levelfuse::io
