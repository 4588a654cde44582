// PoissonRecon (screened Poisson, as Open3D 0.16 ships it) as a benchmark peer.

#include "peers/PoissonRecon.h"

#include "peers/Open3DMesh.h"

#include <open3d/geometry/KDTreeSearchParam.h>
#include <open3d/geometry/PointCloud.h>

namespace levelfuse::peers {

PeerMesh poissonReconstruct(const std::vector<PoissonScan>& scans, int depth, int threads) {
  open3d::geometry::PointCloud all;
  for (const PoissonScan& scan : scans) {
    open3d::geometry::PointCloud cloud;
    for (const auto& p : scan.points) cloud.points_.emplace_back(p[0], p[1], p[2]);
    cloud.EstimateNormals(open3d::geometry::KDTreeSearchParamKNN(12));
    if (scan.scannerPosition)
      cloud.OrientNormalsTowardsCameraLocation(
          Eigen::Vector3d((*scan.scannerPosition)[0], (*scan.scannerPosition)[1], (*scan.scannerPosition)[2]));
    else
      cloud.OrientNormalsToAlignWithDirection(
          Eigen::Vector3d(scan.towardScanner[0], scan.towardScanner[1], scan.towardScanner[2]));
    // Row vectors: p_world = p * M, so the rotation acts as its transpose on columns.
    Eigen::Matrix3d rotation;
    Eigen::Vector3d translation;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) rotation(c, r) = scan.scanToWorld[4 * r + c];
      translation[r] = scan.scanToWorld[12 + r];
    }
    for (std::size_t i = 0; i < cloud.points_.size(); ++i) {
      all.points_.push_back(rotation * cloud.points_[i] + translation);
      all.normals_.push_back(rotation * cloud.normals_[i]);
    }
  }
  const auto reconstructed = open3d::geometry::TriangleMesh::CreateFromPointCloudPoisson(
      all, static_cast<std::size_t>(depth), 0.0f, 1.1f, false, threads);
  return fromOpen3D(*std::get<0>(reconstructed));
}

}  // namespace levelfuse::peers
