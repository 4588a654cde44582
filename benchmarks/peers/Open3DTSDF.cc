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

PeerMesh open3dTsdf(const std::vector<DepthFrameFile>& frames, const DepthCamera& camera, const TsdfSettings& settings) {
  using open3d::pipelines::integration::ScalableTSDFVolume;
  using open3d::pipelines::integration::TSDFVolumeColorType;
  ScalableTSDFVolume volume(settings.voxel, settings.truncation, TSDFVolumeColorType::NoColor);
  const open3d::camera::PinholeCameraIntrinsic intrinsic(camera.width, camera.height, camera.fx, camera.fy, camera.cx,
                                                         camera.cy);
  for (const DepthFrameFile& frame : frames) {
    open3d::geometry::Image depth;
    if (!open3d::io::ReadImage(frame.depthPng, depth) || depth.num_of_channels_ != 1 ||
        depth.bytes_per_channel_ != 2 || depth.width_ != camera.width || depth.height_ != camera.height)
      throw std::runtime_error(frame.depthPng + ": not a " + std::to_string(camera.width) + "x" +
                               std::to_string(camera.height) + " 16-bit depth PNG that Open3D can read");
    open3d::geometry::RGBDImage rgbd;  // no colour: only the depth is integrated
    rgbd.depth_ = *depth.ConvertDepthToFloatImage(settings.depthScale, settings.maxDepth);
    // Row vectors: p_world = p * M, so the camera-to-world matrix for column vectors is M's transpose.
    Eigen::Matrix4d cameraToWorld;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) cameraToWorld(c, r) = frame.cameraToWorld[4 * r + c];
    volume.Integrate(rgbd, intrinsic, cameraToWorld.inverse());  // Open3D wants world-to-camera
  }
  return fromOpen3D(*volume.ExtractTriangleMesh());
}

}  // namespace levelfuse::peers
