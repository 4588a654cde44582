// levelfuse: folders of the TUM RGB-D benchmark (Sturm et al. 2012).
//
// A folder holds `depth.txt`, lines `timestamp filename` naming 16-bit depth
// PNGs (relative to the folder) of 5000 units per metre, and
// `groundtruth.txt`, lines `timestamp tx ty tz qx qy qz qw`: the camera's
// optical centre and orientation (a unit quaternion) in the world, i.e. the
// camera-to-world motion p_world = R(q) p_camera + t. Lines starting with '#'
// are comments; timestamps are seconds. Each frame takes the pose of the
// nearest timestamp, which must lie within a tolerance (0.02 s by default, as
// the benchmark's associate.py) of the frame's.
//
// If the folder holds `rgb.txt` (lines `timestamp filename` naming colour
// PNGs), each frame takes the colours of the colour image nearest in time
// within the same tolerance: the benchmark's depth images are registered to
// its colour camera, pixel for pixel (a frame without one has no colour).
//
// Intrinsics: `camera-intrinsics.txt` (a 3x3 matrix as in the 7-Scenes
// layout) if the folder holds one; otherwise those of the Kinect the folder's
// name says (`freiburg2` or `freiburg3`, as the benchmark's sequences are
// named), and of Freiburg 1 for any other name.
#pragma once

#include <levelfuse/io/scans/ScanLoadOptions.h>
#include <levelfuse/scan/RangeMap.h>

#include <openvdb/math/Mat4.h>

#include <string>
#include <vector>

namespace levelfuse::io {

/// Units per metre of TUM RGB-D depth PNGs.
constexpr double kTumDepthUnitsPerMetre = 5000.0;

/// A line of depth.txt or rgb.txt: an image and its time.
struct TumFrame {
  double time = 0.0;
  std::string file;  ///< as written
  int line = 0;
};

/// A line of groundtruth.txt.
struct TumPose {
  double time = 0.0;
  openvdb::math::Mat4d cameraToWorld;  ///< OpenVDB's row-vector layout
  int line = 0;
};

/// The folder's lists (depth.txt or rgb.txt, and groundtruth.txt), strictly: every line that is not a comment holds
/// exactly the fields its format names, finite numbers, unit quaternions.
/// Throw InputError naming the file and line; a file without entries is refused.
std::vector<TumFrame> readTumImageList(const std::string& path);
std::vector<TumPose> readTumTrajectory(const std::string& path);

/// The pose in `poses` (sorted by time, not empty) nearest to `time`.
const TumPose& nearestPose(const std::vector<TumPose>& poses, double time);

/// True if `folder` holds a depth.txt: a TUM RGB-D folder.
bool isTumFolder(const std::string& folder);

/// The folder's intrinsics (see above).
PinholeProjection tumIntrinsics(const std::string& folder);

/// Every `options.frameStride`-th frame of depth.txt as a range map posed by
/// groundtruth.txt. A frame without a pose within the tolerance, or whose
/// image is missing or unreadable, is refused with InputError naming it.
std::vector<RangeMap> loadTumFolder(const std::string& folder, const ScanLoadOptions& options = {});

}  // namespace levelfuse::io
