// Folders of depth frames for tests: small TUM RGB-D and 7-Scenes layouts of a
// synthetic scene, the plane z = planeZ, rendered exactly from each pose.
#pragma once

#include <levelfuse/scan/RangeMap.h>

#include <openvdb/math/Quat.h>
#include <openvdb/math/Vec3.h>

#include <string>
#include <vector>

namespace levelfuse::test {

/// The intrinsics of the tests' small depth cameras.
inline const PinholeProjection kSmallCamera{12.0, 12.0, 7.5, 5.5};

/// A camera pose: camera-to-world, p_world = R(rotation) p_camera + position.
struct CameraPose {
  openvdb::Vec3d position{0.0};
  openvdb::math::Quatd rotation{0.0, 0.0, 0.0, 1.0};
};

/// The rotation of `degrees` about the unit `axis`.
openvdb::math::Quatd rotationAbout(const openvdb::Vec3d& axis, double degrees);

/// The depths (metres along the optical axis) of the plane z = planeZ seen
/// from `pose`; 0 where a ray misses it. Row-major.
std::vector<double> renderPlane(const CameraPose& pose, const PinholeProjection& k, int width, int height,
                                double planeZ);

/// The largest distance of a map's readings (world points) from the plane z = planeZ.
double farthestFromPlane(const RangeMap& map, double planeZ);

struct TumFixture {
  int width = 16, height = 12;
  PinholeProjection intrinsics = kSmallCamera;
  bool writeIntrinsics = true;  ///< camera-intrinsics.txt, else the default Kinect's
  double planeZ = 2.0;
  struct Pose {
    double time;
    CameraPose pose;
  };
  std::vector<Pose> poses;          ///< groundtruth.txt, in this order
  std::vector<double> frameTimes;   ///< depth.txt; each frame rendered from its nearest pose
};

/// Writes `folder`/depth.txt, groundtruth.txt, depth/<time>.png (5000 units
/// per metre) and, if asked, camera-intrinsics.txt.
void writeTumFolder(const std::string& folder, const TumFixture& fixture);

/// Writes a 7-Scenes folder: frame-00000N.depth.png (millimetres) and
/// .pose.txt for each pose, and camera-intrinsics.txt.
void writeSevenScenesFolder(const std::string& folder, const std::vector<CameraPose>& poses,
                            const PinholeProjection& k, int width, int height, double planeZ);

}  // namespace levelfuse::test
