// levelfuse: how rough a surface is where the scans saw it.
#pragma once

#include <levelfuse/levelset/Mesh.h>

#include <openvdb/openvdb.h>

#include <cstddef>
#include <vector>

namespace levelfuse {

/// The mean curvature H = (k1 + k2) / 2 of a surface (1 / world units) at the
/// surface positions nearest the scans' points. A surface that fits the noise
/// of the scans is bumpy, and its curvature there grows: `rms` is the ruler
/// with which a smoother surface (a larger `beta`) and a closer fit are set
/// side by side. The mesh of a sphere of radius R measures a median |H| of
/// 1 / R (its flat facets, seen by a finer ruler, lift the rms a few percent
/// above); a plane measures 0.
struct SurfaceRoughness {
  std::size_t readings = 0;          ///< points within reach of the surface, measured
  double rms = 0.0;                  ///< root mean square of H
  double medianAbsolute = 0.0;       ///< median of |H|
  double p90Absolute = 0.0;          ///< 90th percentile of |H|
};

/// The roughness of any mesh (a levelfuse surface or another tool's), measured
/// on one ruler: the mesh is stored as an OpenVDB level set of `rulerVoxel`
/// (world units; a few times finer than the features of interest, e.g. 0.1 mm
/// for the Stanford bunny) and its mean curvature, by second-order central
/// differences, is interpolated at each point projected onto the zero set.
/// Points farther than `reach` (world units) from the surface are skipped, as
/// strays. Throws std::invalid_argument for a mesh without triangles or a
/// non-positive ruler or reach.
SurfaceRoughness measureRoughness(const TriangleMesh& mesh, const std::vector<openvdb::Vec3d>& points,
                                  double rulerVoxel, double reach);

}  // namespace levelfuse
