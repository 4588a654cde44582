// levelfuse: loading scans by what the path is.

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/InputFile.h>
#include <levelfuse/io/scans/Manifest.h>
#include <levelfuse/io/scans/E57Scans.h>
#include <levelfuse/io/scans/PtxScans.h>
#include <levelfuse/io/scans/Scans.h>
#include <levelfuse/io/scans/TumScans.h>

#include "../FileExtension.h"
#include "ScanDelivery.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <utility>

namespace levelfuse::io {

namespace {

namespace fs = std::filesystem;

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::vector<RangeMap> loadDepthFolder(const fs::path& folder, const ScanLoadOptions& options) {
  checkDepthOptions(options, folder.string());
  std::vector<fs::path> frames;
  std::error_code ec;  // the non-throwing overloads throughout: a folder may be unreadable
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (it->is_regular_file(ec) && (endsWith(name, ".depth.png") || endsWith(name, ".depth.pfm") ||
                                    endsWith(name, ".depth.exr")))
      frames.push_back(it->path());
  }
  if (ec) throw InputError(folder.string(), "cannot be read (" + ec.message() + ")");
  if (frames.empty())
    throw InputError(folder.string(), "no depth frames (*.depth.png, *.depth.pfm or *.depth.exr) in this folder");
  std::sort(frames.begin(), frames.end());
  const fs::path intrinsicsFile = folder / "camera-intrinsics.txt";
  if (!fs::exists(intrinsicsFile, ec))
    throw InputError(folder.string(), "no camera-intrinsics.txt (the 3x3 pinhole intrinsics) in this folder");
  const PinholeProjection intrinsics = readIntrinsics(intrinsicsFile.string());
  return deliverStridedFrames(
      frames.size(),
      [&](std::size_t f) {
        const std::string image = frames[f].string();
        const std::string stem = image.substr(0, image.size() - std::string(".depth.png").size());
        const std::string pose = stem + ".pose.txt";
        std::error_code missing;
        if (!fs::exists(pose, missing)) throw InputError(image, "no pose beside it (expected " + pose + ")");
        return loadDepthFrame(image, intrinsics, readPose(pose), options, 0.001);
      },
      options);
}

/// The scans of a reader that reads them all first and asked which are wanted
/// itself (a .conf file, a manifest), handed over if the options take them.
std::vector<RangeMap> handedOverAsWanted(std::vector<RangeMap> maps, const ScanLoadOptions& options) {
  if (!options.take) return maps;
  ScanDelivery scans(options);
  for (RangeMap& m : maps) scans.deliver(std::move(m));
  return {};
}

}  // namespace

std::vector<RangeMap> loadScans(const std::string& path, const ScanLoadOptions& options) {
  requireInputFile(path, /*folderToo=*/true);
  std::error_code ec;
  if (fs::is_directory(path, ec))
    return isTumFolder(path) ? loadTumFolder(path, options) : loadDepthFolder(path, options);
  if (!fs::exists(path, ec)) throw InputError(path, "no such file or folder");
  const std::string extension = detail::lowercaseExtension(path);
  if (extension == ".conf") {
    StanfordScanOptions stanford = options.stanford;
    stanford.interrupter = options.interrupter;
    stanford.progress = options.progress;
    stanford.wanted = options.wanted;
    stanford.memoryBudget = options.memoryBudget;
    return handedOverAsWanted(loadStanfordScans(path, stanford), options);
  }
  if (extension == ".json") return handedOverAsWanted(loadManifest(path, options), options);
  if (extension == ".ptx") return loadPtxScans(path, options);
  if (extension == ".e57") return loadE57Scans(path, options);
  throw InputError(path, "not a kind of scan levelfuse reads: give a Stanford .conf file, a JSON manifest "
                         "(.json), a PTX file (.ptx), an E57 file (.e57) or a folder of depth frames (7-Scenes or "
                         "TUM RGB-D)");
}

}  // namespace levelfuse::io
