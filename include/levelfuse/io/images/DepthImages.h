// levelfuse: depth images of depth cameras (Kinect, 7-Scenes, TUM, KinectFusion).
//
// A depth image holds per pixel the depth z along the camera's optical axis.
// 16-bit PNG images store it in integer units (millimetres: scale 0.001);
// PFM and EXR images store metres as floats. Camera intrinsics come as a 3x3
// matrix, poses as a 4x4 camera-to-world matrix, both as plain text.
#pragma once

#include <levelfuse/core/MemoryBudget.h>
#include <levelfuse/io/AtomicWrite.h>
#include <levelfuse/scan/RangeMap.h>

#include <openvdb/math/Mat4.h>

#include <cstdint>
#include <string>
#include <vector>

namespace levelfuse::io {

struct DepthImage {
  int width = 0, height = 0;
  std::vector<float> depth;  ///< row-major, metres; NaN where there is no reading
  double step = 0.0;  ///< the depths are whole multiples of this (metres; a PNG's scale), 0 if not
};

/// A 16-bit depth image's samples as they are stored, row-major.
struct DepthSamples {
  int width = 0, height = 0;
  std::vector<std::uint16_t> samples;
};

/// Depths held as integers (a 16-bit depth image's samples, row-major):
/// `scale` metres per unit, the values in `invalid` no reading. `scale` must
/// be positive and finite (std::invalid_argument).
DepthImage depthImageFromIntegers(int width, int height, const std::uint16_t* samples, double scale,
                                  const std::vector<unsigned>& invalid = {0, 65535});
/// The samples of a 16-bit grayscale PNG, unscaled; other bit depths and
/// colour types are refused (InputError), and so is every image reader's
/// image that would need more memory than `budget` allows.
DepthSamples readDepthPngSamples(const std::string& path, const MemoryBudget& budget = {});
/// A 16-bit grayscale PNG; `scale` converts its integers to metres; the values
/// in `invalid` (0 and 65535 by default) mean no reading. Other bit depths and
/// colour types are refused.
DepthImage readDepthPng(const std::string& path, double scale = 0.001,
                        const std::vector<unsigned> invalid = {0u, 65535u}, const MemoryBudget& budget = {});
/// A single-channel float PFM ("Pf") in metres; non-finite values mean no
/// reading, and so do non-positive ones unless `positiveOnly` is false (range
/// maps of parallel rays may hold negative readings).
DepthImage readDepthPfm(const std::string& path, bool positiveOnly = true, const MemoryBudget& budget = {});
/// Writes `image` as a little-endian single-channel PFM (NaN where there is no
/// reading), atomically.
void writeDepthPfm(const std::string& path, const DepthImage& image);
/// The same, as one of a run's outputs: committed with the others (AtomicWrite.h).
void writeDepthPfm(OutputSet& outputs, const std::string& path, const DepthImage& image);
/// A float EXR with a Z, Y, R or depth channel, in metres (if levelfuse was
/// built with OpenEXR; otherwise InputError says so).
DepthImage readDepthExr(const std::string& path, const MemoryBudget& budget = {});
/// Any of the above, by file extension (.png, .pfm, .exr).
DepthImage readDepthImage(const std::string& path, double pngScale = 0.001, const MemoryBudget& budget = {});

/// Drops the readings deeper than `maxDepth` (metres along the optical axis):
/// far readings of depth cameras are the noisiest.
void dropReadingsBeyond(DepthImage& image, double maxDepth);

/// A 3x3 intrinsics matrix as text: fx 0 cx / 0 fy cy / 0 0 1.
PinholeProjection readIntrinsics(const std::string& path);
/// A 4x4 camera-to-world matrix as text (column-vector convention, translation
/// in the last column), returned in OpenVDB's row-vector layout.
openvdb::math::Mat4d readPose(const std::string& path);
/// The same from 16 numbers in row-major order, e.g. from a JSON manifest;
/// `where` names the source in errors.
openvdb::math::Mat4d poseFromRowMajor(const std::vector<double>& values, const std::string& file,
                                      const std::string& where);

/// Per-reading noise of a depth camera (scan/RangeMap.h).
using DepthNoise = levelfuse::DepthNoise;

/// One depth frame as a pinhole range map (the image's depths move into it).
RangeMap depthFrame(DepthImage image, const PinholeProjection& intrinsics, const openvdb::math::Mat4d& cameraToWorld,
                    const DepthNoise& noise, const std::string& name);

}  // namespace levelfuse::io
