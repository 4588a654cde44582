// Open3D's ScalableTSDFVolume (Open3D 0.16) as a benchmark peer: depth frames
// integrated into a truncated signed distance function (Curless and Levoy
// 1996, as in KinectFusion) on sparse blocks of voxels, then marching cubes.
// This header includes no Open3D or OpenVDB header, so the two never meet in
// one translation unit.
#pragma once

#include "peers/PeerMesh.h"

#include <array>
#include <string>
#include <vector>

namespace levelfuse::peers {

/// A depth frame on disk as Open3D's users feed it.
struct DepthFrameFile {
  std::string depthPng;                  ///< 16-bit PNG, integer depth units
  std::array<double, 16> cameraToWorld{};  ///< row-major, points as row vectors: p_world = p * M
};

/// A depth frame in memory: depths along the optical axis, world units,
/// row-major, 0 where there is no reading.
struct DepthFrameImage {
  std::vector<float> depth;
  std::array<double, 16> cameraToWorld{};  ///< row-major, points as row vectors: p_world = p * M
};

struct DepthCamera {
  int width = 640, height = 480;
  double fx = 585.0, fy = 585.0, cx = 320.0, cy = 240.0;  ///< pixels
};

struct TsdfSettings {
  double voxel = 0.01;         ///< world units
  double truncation = 0.04;    ///< sdf_trunc, world units (4 voxels is the usual choice)
  double depthScale = 1000.0;  ///< PNG units per world unit (millimetres: 1000)
  double maxDepth = 4.0;       ///< readings beyond it are dropped (depth_trunc), world units
};

/// Reads each frame's PNG with Open3D, integrates it without colour
/// (TSDFVolumeColorType::NoColor) with its world-to-camera extrinsic, and
/// extracts the triangle mesh by marching cubes. Open3D runs its loops with
/// OpenMP on its default number of threads (OMP_NUM_THREADS, OMP_WAIT_POLICY). Throws std::runtime_error for a
/// PNG that Open3D cannot read or whose size is not the camera's.
PeerMesh open3dTsdf(const std::vector<DepthFrameFile>& frames, const DepthCamera& camera, const TsdfSettings& settings);
/// The same from frames in memory (their depths as they are: no depth scale),
/// readings beyond the settings' maximum depth dropped. Throws
/// std::invalid_argument for a frame whose size is not the camera's.
PeerMesh open3dTsdf(const std::vector<DepthFrameImage>& frames, const DepthCamera& camera, const TsdfSettings& settings);

}  // namespace levelfuse::peers
