// levelfuse: the mean curvature of a surface where the scans saw it.

#include <levelfuse/recon/SurfaceRoughness.h>

#include <openvdb/tools/GridOperators.h>
#include <openvdb/tools/Interpolation.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace levelfuse {

SurfaceRoughness measureRoughness(const TriangleMesh& mesh, const std::vector<openvdb::Vec3d>& points,
                                  double rulerVoxel, double reach) {
  if (mesh.triangleCount() == 0) throw std::invalid_argument("measureRoughness: the mesh has no triangles");
  if (!(rulerVoxel > 0.0) || !(reach > 0.0))
    throw std::invalid_argument("measureRoughness: the ruler's voxel and the reach must be positive");
  // The band holds `reach`, then a voxel for the trilinear samples near it and
  // one for the curvature's central differences.
  const float halfWidth = static_cast<float>(std::ceil(reach / rulerVoxel) + 2.0);
  const openvdb::FloatGrid::Ptr distance = levelSetFromMesh(mesh, rulerVoxel, halfWidth);
  const openvdb::math::Transform& transform = distance->transform();
  const openvdb::FloatGrid::Ptr curvature = openvdb::tools::meanCurvature(*distance);

  constexpr double kSkipped = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> h(points.size(), kSkipped);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size()), [&](const tbb::blocked_range<std::size_t>& r) {
    openvdb::tools::GridSampler<openvdb::FloatGrid, openvdb::tools::BoxSampler> phi(*distance), meanH(*curvature);
    const auto accessor = distance->getConstAccessor();
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      const double d = phi.wsSample(points[i]);
      if (!(std::fabs(d) < reach)) continue;
      // One step along the gradient of the signed distance reaches the zero set.
      const openvdb::Coord ijk = transform.worldToIndexNodeCentered(points[i]);
      openvdb::Vec3d gradient = openvdb::math::ISGradient<openvdb::math::CD_2ND>::result(accessor, ijk);
      if (gradient.lengthSqr() < 1e-12) continue;
      gradient.normalize();
      h[i] = meanH.wsSample(points[i] - d * gradient);
    }
  });

  std::vector<double> absolute;
  absolute.reserve(h.size());
  double sumSq = 0.0;
  for (const double v : h)
    if (!std::isnan(v)) {
      absolute.push_back(std::fabs(v));
      sumSq += v * v;
    }
  SurfaceRoughness roughness;
  roughness.readings = absolute.size();
  if (absolute.empty()) return roughness;
  const double n = static_cast<double>(absolute.size());
  roughness.rms = std::sqrt(sumSq / n);
  std::sort(absolute.begin(), absolute.end());
  roughness.medianAbsolute = absolute[absolute.size() / 2];
  roughness.p90Absolute = absolute[std::min(absolute.size() - 1, static_cast<std::size_t>(0.9 * n))];
  return roughness;
}

}  // namespace levelfuse
