// Open3D's ScalableTSDFVolume (Open3D 0.16) as a benchmark peer.

#include "peers/Open3DTSDF.h"

#include "peers/Open3DMesh.h"

#include <open3d/camera/PinholeCameraIntrinsic.h>
#include <open3d/geometry/Image.h>
#include <open3d/geometry/RGBDImage.h>
#include <open3d/io/ImageIO.h>
#include <open3d/pipelines/integration/ScalableTSDFVolume.h>

#include <stdexcept>

namespace levelfuse::peers {

namespace {

using open3d::pipelines::integration::ScalableTSDFVolume;

ScalableTSDFVolume volumeOf(const TsdfSettings& settings) {
  return ScalableTSDFVolume(settings.voxel, settings.truncation,
                            open3d::pipelines::integration::TSDFVolumeColorType::NoColor);
}

open3d::camera::PinholeCameraIntrinsic intrinsicOf(const DepthCamera& camera) {
  return open3d::camera::PinholeCameraIntrinsic(camera.width, camera.height, camera.fx, camera.fy, camera.cx,
                                                camera.cy);
}

/// Integrates a float depth image (metres) seen from `cameraToWorld` (row vectors).
void integrate(ScalableTSDFVolume& volume, const open3d::camera::PinholeCameraIntrinsic& intrinsic,
               open3d::geometry::Image depth, const std::array<double, 16>& cameraToWorldRows) {
  open3d::geometry::RGBDImage rgbd;  // no colour: only the depth is integrated
  rgbd.depth_ = std::move(depth);
  // Row vectors: p_world = p * M, so the camera-to-world matrix for column vectors is M's transpose.
  Eigen::Matrix4d cameraToWorld;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) cameraToWorld(c, r) = cameraToWorldRows[4 * r + c];
  volume.Integrate(rgbd, intrinsic, cameraToWorld.inverse());  // Open3D wants world-to-camera
}

}  // namespace

PeerMesh open3dTsdf(const std::vector<DepthFrameFile>& frames, const DepthCamera& camera, const TsdfSettings& settings) {
  ScalableTSDFVolume volume = volumeOf(settings);
  const open3d::camera::PinholeCameraIntrinsic intrinsic = intrinsicOf(camera);
  for (const DepthFrameFile& frame : frames) {
    open3d::geometry::Image depth;
    if (!open3d::io::ReadImage(frame.depthPng, depth) || depth.num_of_channels_ != 1 ||
        depth.bytes_per_channel_ != 2 || depth.width_ != camera.width || depth.height_ != camera.height)
      throw std::runtime_error(frame.depthPng + ": not a " + std::to_string(camera.width) + "x" +
                               std::to_string(camera.height) + " 16-bit depth PNG that Open3D can read");
    integrate(volume, intrinsic, *depth.ConvertDepthToFloatImage(settings.depthScale, settings.maxDepth),
              frame.cameraToWorld);
  }
  return fromOpen3D(*volume.ExtractTriangleMesh());
}

PeerMesh open3dTsdf(const std::vector<DepthFrameImage>& frames, const DepthCamera& camera, const TsdfSettings& settings) {
  ScalableTSDFVolume volume = volumeOf(settings);
  const open3d::camera::PinholeCameraIntrinsic intrinsic = intrinsicOf(camera);
  const std::size_t pixels = static_cast<std::size_t>(camera.width) * static_cast<std::size_t>(camera.height);
  for (const DepthFrameImage& frame : frames) {
    if (frame.depth.size() != pixels) throw std::invalid_argument("open3dTsdf: a frame is not the camera's size");
    open3d::geometry::Image depth;
    depth.Prepare(camera.width, camera.height, 1, 4);
    float* out = depth.PointerAs<float>();
    for (std::size_t i = 0; i < pixels; ++i)
      out[i] = frame.depth[i] > 0.0f && frame.depth[i] <= settings.maxDepth ? frame.depth[i] : 0.0f;
    integrate(volume, intrinsic, std::move(depth), frame.cameraToWorld);
  }
  return fromOpen3D(*volume.ExtractTriangleMesh());
}

}  // namespace levelfuse::peers
