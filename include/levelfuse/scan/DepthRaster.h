// levelfuse: triangles seen along a line of sight, as a depth image.
//
// A scan that comes as a triangulated set of samples (a Stanford range grid)
// becomes an orthographic range map by rasterising its triangles along the
// line of sight: each pixel centre inside a triangle takes the depth of the
// triangle's plane there, the nearest triangle to the scanner winning.
//
// Pixel centres alone lose the samples on the scan's boundary: a sample on
// the edge of the triangulated area has pixel centres outside it on one side,
// and the bilinear interpolation of a range map needs all four pixels around
// a point. Pixels within `edgeExtension` pixels outside the triangles take the
// plane of the nearest triangle, so that every sample the triangles reach
// (including those on the boundary) lies in a cell of four readings. An
// extension of 1.5 pixels covers the cell around every boundary sample (its
// corners are at most sqrt(2) pixels away) and extrapolates no plane farther.
#pragma once

#include <openvdb/Types.h>

#include <vector>

namespace levelfuse {

/// Depths of `triangles` on a `width` x `height` grid of pixels, row-major,
/// NaN where none reaches. `vertices` are (u, v, depth): pixel coordinates
/// (pixel (i, j) has its centre at u = i, v = j) and the depth along the line
/// of sight, smaller nearer the scanner.
std::vector<float> rasteriseDepth(const std::vector<openvdb::Vec3d>& vertices,
                                  const std::vector<openvdb::Vec3I>& triangles, int width, int height,
                                  double edgeExtension = 0.0);

}  // namespace levelfuse
