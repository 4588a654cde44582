// levelfuse: point clouds with their sensor's pose (a LiDAR sweep, a
// terrestrial scan exported as points), binned into spherical range maps.
//
// Point files, one set of points per scan:
//
//  - XYZ text (`.xyz`, `.txt`): one point a line, fields separated by spaces
//    or tabs; blank lines and lines starting with '#' are skipped. Every
//    point line has the same number of fields as the first:
//      3  x y z
//      4  x y z intensity
//      6  x y z r g b
//      7  x y z intensity r g b
//    r, g, b are whole numbers from 0 to 255; the intensity is read, checked
//    finite and not kept.
//  - PLY (`.ply`, ASCII or binary, readPly): the element `vertex` with scalar
//    x, y, z of any numeric type; colours from its `red`, `green`, `blue`
//    (all three or none) of type uchar (0 to 255) or float or double (0 to 1,
//    scaled to 0 to 255 and rounded). Other elements (faces) are ignored.
//  - KITTI velodyne sweeps (`.bin`): float32 little-endian x y z reflectance
//    per point, 16 bytes each and nothing else, in the velodyne's frame
//    (x forward, y left, z up).
//
// KITTI odometry poses:
//
//  - `calib.txt`: lines `NAME: numbers`; `Tr:` gives 12 numbers, the 3x4
//    velodyne-to-camera-0 transform row by row (column vectors:
//    p_camera = Tr p_velodyne). The cameras' `P0:` to `P3:` are not used.
//  - `poses/NN.txt`: one line of 12 numbers per frame (line 1 is frame 0),
//    the 3x4 camera-0-to-world transform of that frame row by row, the world
//    being camera 0's frame at frame 0 (x right, y down, z forward).
//  - The velodyne-to-world pose of frame i is pose_i Tr (column vectors);
//    levelfuse's matrices are OpenVDB's row-vector layout (world = p M), so it
//    is Tr^T pose_i^T there.
//
// Every reader is strict: a number that is not finite, a colour out of its
// range, mixed field counts, a file without points, a KITTI file whose size
// is not a whole number of points, a rotation that is not rigid or a frame
// beyond the poses file are refused with an InputError naming the file (and
// line).
#pragma once

#include <levelfuse/core/Interrupter.h>
#include <levelfuse/core/MemoryBudget.h>
#include <levelfuse/scan/Colour.h>
#include <levelfuse/scan/RangeMap.h>
#include <levelfuse/scan/SphericalScan.h>

#include <openvdb/Types.h>
#include <openvdb/math/Mat4.h>
#include <openvdb/math/Vec3.h>

#include <optional>
#include <string>
#include <vector>

namespace levelfuse::io {

/// The points of one scan, in the frame their file gives them in.
struct PointCloud {
  std::vector<openvdb::Vec3d> points;
  /// Per point if the file gives colours, else empty.
  std::vector<Rgb8> colours;
};

/// An XYZ text file (see above); `interrupter` is asked every 65536 lines.
PointCloud readXyzPoints(const std::string& path, const Interrupter& interrupter = {});
/// The vertices of a PLY file (see above), refused if they would need more
/// memory than `budget` allows.
PointCloud readPlyPoints(const std::string& path, const MemoryBudget& budget = {});
/// A KITTI velodyne `.bin` sweep (see above), read whole at once; refused if
/// it would need more memory than `budget` allows.
PointCloud readKittiBin(const std::string& path, const MemoryBudget& budget = {});
/// An XYZ or PLY file by its extension (`.xyz`, `.txt`, `.ply`, any case).
PointCloud readPointCloud(const std::string& path, const Interrupter& interrupter = {},
                          const MemoryBudget& budget = {});

/// The `Tr:` line of a KITTI odometry `calib.txt`: velodyne to camera 0, in
/// OpenVDB's row-vector layout.
openvdb::math::Mat4d readKittiVelodyneToCamera(const std::string& calibPath);
/// Frame `frame`'s line of a KITTI odometry poses file: camera 0 to the
/// world, in OpenVDB's row-vector layout. The whole file is checked.
openvdb::math::Mat4d readKittiCameraToWorld(const std::string& posesPath, long long frame);
/// The velodyne-to-world pose of a frame: pose Tr (column vectors), in
/// OpenVDB's row-vector layout.
openvdb::math::Mat4d kittiVelodyneToWorld(const openvdb::math::Mat4d& cameraToWorld,
                                          const openvdb::math::Mat4d& velodyneToCamera);

/// Points given in the world taken into the sensor's frame (the inverse of
/// its rigid pose).
std::vector<openvdb::Vec3d> pointsInSensorFrame(const std::vector<openvdb::Vec3d>& worldPoints,
                                                const openvdb::math::Mat4d& sensorToWorld);

/// A map may have at most this many pixels per point (and a few more): steps
/// far finer than the points' spacing are refused.
inline constexpr double kMaxPixelsPerCloudPoint = 16.0;

/// Angular steps finer than this (radians, about 0.2 seconds of arc; the
/// finest terrestrial scanners step 10 times more) are refused.
inline constexpr double kMinCloudStep = 1e-6;

/// The points (in the sensor's frame, z up) binned into a spherical range map
/// (sphericalMapFromPoints) with `steps`, or with the steps estimated from
/// the points (estimateAngularSteps), its readings of noise `sigma`, named
/// `name`, with the points' `colours` if given (one per point). Throws InputError naming `path` if the steps cannot be
/// estimated, are finer than kMinCloudStep, would make more than
/// kMaxPixelsPerCloudPoint pixels per point (refused before the map is
/// allocated), or make no map.
RangeMap rangeMapFromPointCloud(const std::vector<openvdb::Vec3d>& sensorPoints,
                                const openvdb::math::Mat4d& sensorToWorld, const std::optional<AngularSteps>& steps,
                                double sigma, const std::string& path, const std::string& name,
                                const std::vector<Rgb8>& colours = {});

/// A spinning LiDAR's sweep (points in the sensor's frame, z up, in the order
/// the file lists them) as range maps: without `steps`, a sweep listed laser
/// by laser in firing order (KITTI's) as a map per block of lasers that
/// share an apex (lasersInFiringOrder, sweepRangeMaps); with them, or in
/// another order, one map binned by direction (rangeMapFromPointCloud).
/// Throws InputError naming `path` as rangeMapFromPointCloud does, or if a
/// block's lasers do not have distinct elevations.
std::vector<RangeMap> rangeMapsOfSweep(const std::vector<openvdb::Vec3d>& sensorPoints,
                                       const openvdb::math::Mat4d& sensorToWorld,
                                       const std::optional<AngularSteps>& steps, double sigma, const std::string& path,
                                       const std::string& name);

}  // namespace levelfuse::io
