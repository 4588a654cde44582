// levelfuse: KITTI odometry's calib.txt and poses files (see PointScans.h).

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/images/DepthImages.h>
#include <levelfuse/io/scans/PointScans.h>

#include "../TextLineReader.h"

#include <optional>
#include <string>
#include <vector>

namespace levelfuse::io {

namespace {

using openvdb::math::Mat4d;

/// Numbers of a 3x4 transform, row by row.
constexpr std::size_t kTransformNumbers = 12;

/// The current line's fields from `first` on as a rigid 3x4 transform, row by
/// row (column vectors), in OpenVDB's row-vector layout; `what` names it.
Mat4d transformOnLine(const TextLineReader& lines, std::size_t first, const std::string& what) {
  if (lines.fieldCount() != first + kTransformNumbers)
    lines.fail("expected " + what + ": " + std::to_string(kTransformNumbers) + " numbers (a 3x4 transform row by "
               "row), found " + std::to_string(lines.fieldCount() - first));
  std::vector<double> rowMajor;
  for (std::size_t i = 0; i < kTransformNumbers; ++i) rowMajor.push_back(lines.number(first + i));
  rowMajor.insert(rowMajor.end(), {0.0, 0.0, 0.0, 1.0});
  return poseFromRowMajor(rowMajor, lines.path(), lines.at() + what + ": ");
}

/// Checks that the current line of calib.txt is `NAME: numbers`.
void requireCalibLine(const TextLineReader& lines) {
  const std::string_view key = lines.field(0);
  if (key.size() < 2 || key.back() != ':')
    lines.fail("expected 'NAME: numbers' (KITTI odometry's calib.txt), found " + quote(key));
  for (std::size_t i = 1; i < lines.fieldCount(); ++i) static_cast<void>(lines.number(i));
}

}  // namespace

Mat4d readKittiVelodyneToCamera(const std::string& calibPath) {
  TextLineReader lines(calibPath);
  std::optional<Mat4d> velodyneToCamera;
  std::int64_t trLine = 0;
  while (lines.next()) {
    if (lines.fieldCount() == 0) continue;
    requireCalibLine(lines);
    if (lines.field(0) != "Tr:") continue;
    if (velodyneToCamera)
      lines.fail("a second 'Tr:' line (the first is line " + std::to_string(trLine) + ")");
    velodyneToCamera = transformOnLine(lines, 1, "'Tr:' (velodyne to camera 0)");
    trLine = lines.lineNumber();
  }
  if (!velodyneToCamera)
    throw InputError(calibPath, "no 'Tr:' line: KITTI odometry's calib.txt gives the velodyne-to-camera-0 "
                                "transform there");
  return *velodyneToCamera;
}

Mat4d readKittiCameraToWorld(const std::string& posesPath, long long frame) {
  TextLineReader lines(posesPath);
  std::optional<Mat4d> pose;
  long long frames = 0;
  std::int64_t blankLine = 0;
  while (lines.next()) {
    if (lines.fieldCount() == 0) {
      if (blankLine == 0) blankLine = lines.lineNumber();
      continue;
    }
    if (blankLine != 0)
      lines.fail("a pose after the blank line " + std::to_string(blankLine) +
                 ": the file holds one line per frame, frame 0 on line 1");
    const Mat4d cameraToWorld = transformOnLine(lines, 0, "the pose of frame " + std::to_string(frames));
    if (frames == frame) pose = cameraToWorld;
    ++frames;
  }
  if (frames == 0) throw InputError(posesPath, "no poses: the file is empty or blank");
  if (!pose)
    throw InputError(posesPath, "frame " + std::to_string(frame) + " is beyond the file's " + std::to_string(frames) +
                                    " poses (frames 0 to " + std::to_string(frames - 1) + ")");
  return *pose;
}

Mat4d kittiVelodyneToWorld(const Mat4d& cameraToWorld, const Mat4d& velodyneToCamera) {
  // Column vectors: p_world = pose Tr p_velodyne. Row vectors: p_world =
  // p_velodyne Tr^T pose^T, velodyne to camera first.
  return velodyneToCamera * cameraToWorld;
}

}  // namespace levelfuse::io
