// Fuzzes the TUM RGB-D lists: the input as depth.txt (readTumImageList) and as
// groundtruth.txt (readTumTrajectory), each then in a TUM folder beside a valid
// other list whose frames are the fixtures' depth.png (loadTumFolder: matching
// frames to poses, loading the frames).

#include "FuzzInput.h"
#include "ScanFixtures.h"

#include <levelfuse/io/scans/TumScans.h>

#include <filesystem>

namespace {

namespace fs = std::filesystem;

/// Folders for the fuzzed depth list and the fuzzed trajectory.
std::string depthFolder, poseFolder;

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  using namespace levelfuse;
  fuzz::writeScanFixtures();  // depth.png in the scratch folder
  depthFolder = (fs::path(fuzz::scratchFolder()) / "fuzzed-depth").string();
  poseFolder = (fs::path(fuzz::scratchFolder()) / "fuzzed-poses").string();
  fs::create_directories(depthFolder);
  fs::create_directories(poseFolder);
  fuzz::writeScratchFile("fuzzed-depth/groundtruth.txt", "# timestamp tx ty tz qx qy qz qw\n"
                                                         "1.00 0 0 0 0 0 0 1\n1.01 0.1 0 0 0 0 0.7071068 0.7071068\n");
  fuzz::writeScratchFile("fuzzed-poses/depth.txt",
                         "# timestamp filename\n1.000000 ../depth.png\n1.010000 ../depth.png\n");
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace levelfuse;
  const std::string list = fuzz::writeScratchFile("fuzzed-depth/depth.txt", data, size);
  fuzz::expectOnlyInputErrors([&] { io::readTumImageList(list); });
  fuzz::expectOnlyInputErrors([&] { io::loadTumFolder(depthFolder); });
  const std::string trajectory = fuzz::writeScratchFile("fuzzed-poses/groundtruth.txt", data, size);
  fuzz::expectOnlyInputErrors([&] { io::readTumTrajectory(trajectory); });
  fuzz::expectOnlyInputErrors([&] { io::loadTumFolder(poseFolder); });
  return 0;
}
