// levelfuse: scans from whatever a user points at.
#pragma once

#include <levelfuse/core/Interrupter.h>
#include <levelfuse/io/DepthImages.h>
#include <levelfuse/io/StanfordScans.h>
#include <levelfuse/scan/RangeMap.h>

#include <string>
#include <vector>

namespace levelfuse::io {

struct ScanLoadOptions {
  StanfordScanOptions stanford;  ///< for .conf files: the scanner's direction, sigma, pixel size
  double depthScale = 0.001;     ///< metres per unit of 16-bit depth PNGs
  DepthNoise depthNoise;         ///< sigma of depth-camera readings
  int frameStride = 1;           ///< of a folder of depth frames, every n-th
  Interrupter interrupter;       ///< asked before each scan or frame is read (Interrupted)
};

/// Loads the scans at `path`, by what it is:
///  - a Stanford `.conf` file and the range-grid PLY scans it places;
///  - a JSON manifest (`.json`, see Manifest.h);
///  - a folder of depth frames in the 7-Scenes layout: `*.depth.png` (or
///    `.pfm`, `.exr`) images, each with a `*.pose.txt` camera-to-world pose
///    beside it, and one `camera-intrinsics.txt`.
/// Throws InputError naming the file and the problem.
std::vector<RangeMap> loadScans(const std::string& path, const ScanLoadOptions& options = {});

}  // namespace levelfuse::io
