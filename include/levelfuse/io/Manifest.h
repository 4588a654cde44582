// levelfuse: a JSON manifest that lists scans with their geometry, pose,
// noise and format, so any scanner can be described without code.
//
//   {
//     "scans": [
//       { "format": "stanford-conf", "file": "bun.conf",
//         "toward_scanner": [0, 0, 1], "sigma": 0.0002 },
//       { "format": "stanford-ply", "file": "bun045.ply",
//         "translation": [-0.052, 0.0, -0.011], "quaternion": [0.0055, -0.29, -0.0039, 0.96] },
//       { "format": "depth-png", "file": "frame-000000.depth.png", "depth_scale": 0.001,
//         "intrinsics_file": "camera-intrinsics.txt", "pose_file": "frame-000000.pose.txt" },
//       { "format": "depth-pfm", "file": "d.pfm",
//         "intrinsics": { "fx": 585, "fy": 585, "cx": 320, "cy": 240 },
//         "pose": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1],
//         "sigma": { "minimum": 0.001, "per_square_metre": 0.0015 } }
//     ]
//   }
//
// Paths are relative to the manifest. Formats: stanford-conf, stanford-ply,
// depth-png, depth-pfm, depth-exr. Poses are camera-to-world, 16 numbers in
// row-major order with the translation in the last column.
#pragma once

#include <levelfuse/scan/RangeMap.h>

#include <string>
#include <vector>

namespace levelfuse::io {

/// Loads every scan a manifest lists; InputError names the manifest and the
/// entry (e.g. "scans[2]: 'pose' needs 16 numbers") or the scan file at fault.
std::vector<RangeMap> loadManifest(const std::string& path);

}  // namespace levelfuse::io
