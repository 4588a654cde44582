// Point files for tests: points (and colours) written as XYZ text, PLY
// (ASCII or binary) and KITTI velodyne sweeps, and poses as manifests and
// KITTI's text files write them.
#pragma once

#include <levelfuse/scan/Colour.h>

#include <openvdb/Types.h>
#include <openvdb/math/Mat4.h>
#include <openvdb/math/Vec3.h>

#include <string>
#include <vector>

namespace levelfuse::test {

/// "x y z" lines, or "x y z r g b" with colours, nine significant digits.
std::string xyzText(const std::vector<openvdb::Vec3d>& points, const std::vector<Rgb8>& colours = {});

/// A PLY file of vertices x, y, z (double) and, with colours, red, green,
/// blue (uchar): ASCII, or binary little-endian.
std::string plyPoints(const std::vector<openvdb::Vec3d>& points, const std::vector<Rgb8>& colours, bool binary);

/// A KITTI velodyne sweep: float32 little-endian x y z and a reflectance of 0.5.
std::vector<unsigned char> kittiBinBytes(const std::vector<openvdb::Vec3d>& points);

/// A pose as 12 numbers, the 3x4 top of the column-vector matrix row by row
/// (KITTI's calib.txt and poses files), from OpenVDB's row-vector layout.
std::string kittiTransformText(const openvdb::math::Mat4d& rowVectorPose);

/// A pose as a manifest's "pose": 16 numbers row by row, column vectors.
std::string manifestPose(const openvdb::math::Mat4d& rowVectorPose);

/// Colours that differ from point to point.
std::vector<Rgb8> someColours(std::size_t count);

}  // namespace levelfuse::test
