// levelfuse: scans from whatever a user points at.
#pragma once

#include <levelfuse/core/Interrupter.h>
#include <levelfuse/io/images/DepthImages.h>
#include <levelfuse/io/scans/DepthFrames.h>
#include <levelfuse/io/scans/LoadProgress.h>
#include <levelfuse/io/scans/ScanLoadOptions.h>
#include <levelfuse/io/scans/StanfordScans.h>
#include <levelfuse/scan/RangeMap.h>

#include <cstddef>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace levelfuse::io {

/// Loads the scans at `path`, by what it is:
///  - a Stanford `.conf` file and the range-grid PLY scans it places;
///  - a JSON manifest (`.json`, see Manifest.h);
///  - a PTX file (`.ptx`) of one or more terrestrial laser scans (see PtxScans.h);
///  - an ASTM E57 file (`.e57`) of one or more 3D scans (see E57Scans.h);
///  - a folder of depth frames in the TUM RGB-D layout: `depth.txt` and
///    `groundtruth.txt` (see TumScans.h);
///  - a folder of depth frames in the 7-Scenes layout: `*.depth.png` (or
///    `.pfm`, `.exr`) images, each with a `*.pose.txt` camera-to-world pose
///    beside it, and one `camera-intrinsics.txt`.
/// Throws InputError naming the file and the problem.
std::vector<RangeMap> loadScans(const std::string& path, const ScanLoadOptions& options = {});

}  // namespace levelfuse::io
