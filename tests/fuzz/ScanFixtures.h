// libFuzzer targets: valid files for fuzzed inputs to refer to (a scan for a
// .conf, depth images and camera files for a manifest).
#pragma once

#include <string>

namespace levelfuse::fuzz {

/// A 3 x 3 range-grid scan as ASCII PLY, 1 mm between samples.
std::string rangeGridPly();

/// A 3 x 3 PTX scan of a sphere of radius 2 around the scanner, 128 steps a turn.
std::string sphericalScanPtx();

/// 24 points of a sphere of radius 2 around the scanner, 6 columns x 4 rows,
/// 128 steps a turn: as XYZ text, and as a KITTI velodyne sweep.
std::string sphericalScanXyz();
std::string sphericalScanKittiBin();

/// Writes into the scratch folder: scan.ply (rangeGridPly()), scan.conf (one
/// bmesh line placing it), depth.png (4 x 4, 16-bit), tiny.png (1 x 1),
/// depth.pfm (4 x 4), k.txt (intrinsics), pose.txt (identity), scan.ptx
/// (sphericalScanPtx()), points.xyz and velodyne.bin (sphericalScanXyz(),
/// sphericalScanKittiBin()), and a KITTI calib.txt and poses.txt of two frames.
void writeScanFixtures();

}  // namespace levelfuse::fuzz
