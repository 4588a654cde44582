// levelfuse: TUM RGB-D folders.

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/TextRecords.h>
#include <levelfuse/io/images/ColourImages.h>
#include <levelfuse/io/images/DepthImages.h>
#include <levelfuse/io/scans/DepthFrames.h>
#include <levelfuse/io/scans/TumScans.h>

#include "ScanDelivery.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

namespace levelfuse::io {

namespace {

namespace fs = std::filesystem;

/// Tracked poses are written with four or five decimals: their quaternions
/// are unit to a few parts in ten thousand.
constexpr double kQuaternionTolerance = 1e-2;

void refuseMore(std::istringstream& words, const std::string& path, const std::string& at, const char* after) {
  std::string extra;
  if (words >> extra) throw InputError(path, at + "unexpected '" + extra + "' after the " + after);
}

/// The Kinects of the benchmark, by the name its sequences carry (the depth
/// images are registered to the colour camera, whose intrinsics they take).
PinholeProjection kinectOfSequence(const std::string& name) {
  if (name.find("freiburg2") != std::string::npos) return PinholeProjection{520.9, 521.0, 325.1, 249.7};
  if (name.find("freiburg3") != std::string::npos) return PinholeProjection{535.4, 539.2, 320.1, 247.6};
  return PinholeProjection{517.3, 516.5, 318.6, 255.3};  // Freiburg 1
}

/// A time as the benchmark writes it (microseconds), or a duration briefly.
std::string seconds(double t, bool isTime) {
  char text[64];
  std::snprintf(text, sizeof(text), isTime ? "%.6f" : "%g", t);
  return text;
}

}  // namespace

std::vector<TumFrame> readTumImageList(const std::string& path) {
  std::vector<TumFrame> frames;
  forEachTextRecord(path, [&](int line, const std::string& at, std::istringstream& words) {
    TumFrame f;
    f.line = line;
    f.time = nextNumber(words, path, at, "'timestamp filename'");
    if (!(words >> f.file)) throw InputError(path, at + "expected 'timestamp filename'");
    refuseMore(words, path, at, "file name");
    frames.push_back(f);
  });
  if (frames.empty()) throw InputError(path, "no frames: expected lines 'timestamp filename'");
  return frames;
}

std::vector<TumPose> readTumTrajectory(const std::string& path) {
  std::vector<TumPose> poses;
  forEachTextRecord(path, [&](int line, const std::string& at, std::istringstream& words) {
    double v[8];
    for (double& x : v) x = nextNumber(words, path, at, "'timestamp tx ty tz qx qy qz qw'");
    refuseMore(words, path, at, "quaternion");
    const openvdb::math::Quatd q = unitQuaternion(v[4], v[5], v[6], v[7], path, at, kQuaternionTolerance);
    poses.push_back(TumPose{v[0], rigidMotion(q, openvdb::Vec3d(v[1], v[2], v[3])), line});
  });
  if (poses.empty()) throw InputError(path, "no poses: expected lines 'timestamp tx ty tz qx qy qz qw'");
  std::stable_sort(poses.begin(), poses.end(), [](const TumPose& a, const TumPose& b) { return a.time < b.time; });
  return poses;
}

namespace {

/// The entry of `sorted` (by time, not empty) nearest to `time`.
template <typename Timed>
const Timed& nearestInTime(const std::vector<Timed>& sorted, double time) {
  const auto after =
      std::lower_bound(sorted.begin(), sorted.end(), time, [](const Timed& p, double t) { return p.time < t; });
  if (after == sorted.begin()) return *after;
  if (after == sorted.end()) return sorted.back();
  return time - std::prev(after)->time <= after->time - time ? *std::prev(after) : *after;
}

/// The colour images of rgb.txt, sorted by time; none if the folder has no rgb.txt.
std::vector<TumFrame> colourImagesOf(const fs::path& root) {
  std::error_code ec;
  const fs::path list = root / "rgb.txt";
  if (!fs::is_regular_file(list, ec)) return {};
  std::vector<TumFrame> images = readTumImageList(list.string());
  std::stable_sort(images.begin(), images.end(), [](const TumFrame& a, const TumFrame& b) { return a.time < b.time; });
  return images;
}

/// Gives a frame taken at `time` the colours of the colour image nearest in
/// time, if one lies within `tolerance` seconds (the benchmark's depth images
/// are registered to its colour camera: pixel for pixel).
void colourFrame(RangeMap& frame, double time, const std::vector<TumFrame>& images, const fs::path& root,
                 double tolerance, const MemoryBudget& budget) {
  if (images.empty()) return;
  const TumFrame& nearest = nearestInTime(images, time);
  if (!(std::fabs(nearest.time - time) <= tolerance)) return;
  const std::string image = (root / nearest.file).lexically_normal().string();
  colourRangeMap(frame, readColourPng(image, budget), image);
}

}  // namespace

const TumPose& nearestPose(const std::vector<TumPose>& poses, double time) { return nearestInTime(poses, time); }

bool isTumFolder(const std::string& folder) {
  std::error_code ec;
  return fs::is_regular_file(fs::path(folder) / "depth.txt", ec);
}

PinholeProjection tumIntrinsics(const std::string& folder) {
  const fs::path file = fs::path(folder) / "camera-intrinsics.txt";
  std::error_code ec;
  if (fs::exists(file, ec)) return readIntrinsics(file.string());
  fs::path name = fs::absolute(folder, ec).lexically_normal();
  if (name.filename().empty()) name = name.parent_path();  // a trailing '/'
  return kinectOfSequence(name.filename().string());
}

std::vector<RangeMap> loadTumFolder(const std::string& folder, const ScanLoadOptions& options) {
  checkDepthOptions(options, folder);
  const fs::path root(folder);
  const std::string list = (root / "depth.txt").string(), trajectory = (root / "groundtruth.txt").string();
  std::error_code ec;
  if (!fs::is_regular_file(trajectory, ec))
    throw InputError(folder, "a TUM RGB-D folder (it holds depth.txt) without groundtruth.txt, the camera poses");
  const std::vector<TumFrame> frames = readTumImageList(list);
  const std::vector<TumPose> poses = readTumTrajectory(trajectory);
  const PinholeProjection intrinsics = tumIntrinsics(folder);
  const std::vector<TumFrame> colourImages = colourImagesOf(root);
  return deliverStridedFrames(
      frames.size(),
      [&](std::size_t f) {
        const TumFrame& frame = frames[f];
        const std::string image = (root / frame.file).lexically_normal().string();
        std::error_code missing;
        if (!fs::is_regular_file(image, missing))
          throw InputError(list, "line " + std::to_string(frame.line) + ": depth image '" + frame.file +
                                     "' does not exist (looked for " + image + ")");
        const TumPose& pose = nearestPose(poses, frame.time);
        const double gap = std::fabs(pose.time - frame.time);
        if (!(gap <= options.poseTimeTolerance))
          throw InputError(image, "no pose in groundtruth.txt within " + seconds(options.poseTimeTolerance, false) +
                                      " s of the frame's time " + seconds(frame.time, true) + " (the nearest, line " +
                                      std::to_string(pose.line) + ", is " + seconds(gap, false) + " s away)");
        RangeMap map = loadDepthFrame(image, intrinsics, pose.cameraToWorld, options, 1.0 / kTumDepthUnitsPerMetre);
        colourFrame(map, frame.time, colourImages, root, options.poseTimeTolerance, options.memoryBudget);
        return map;
      },
      options);
}

}  // namespace levelfuse::io
