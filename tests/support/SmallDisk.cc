#include "support/SmallDisk.h"

#include <sys/mount.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <vector>

namespace levelfuse::test {

namespace fs = std::filesystem;

SmallDisk::SmallDisk(std::size_t bytes) {
  std::string pattern = (fs::temp_directory_path() / "levelfuse_small_disk_XXXXXX").string();
  if (!::mkdtemp(pattern.data())) {
    mReason = std::string("cannot make a folder to mount on: ") + std::strerror(errno);
    return;
  }
  mRoot = pattern;
  const std::string options = "size=" + std::to_string(bytes);
  if (::mount("tmpfs", mRoot.c_str(), "tmpfs", MS_NOSUID | MS_NODEV, options.c_str()) != 0) {
    mReason = std::string("cannot mount a small tmpfs (needs root): ") + std::strerror(errno);
    return;
  }
  mMounted = true;
}

SmallDisk::~SmallDisk() {
  if (mMounted) ::umount2(mRoot.c_str(), MNT_DETACH);
  std::error_code ignored;
  if (!mRoot.empty()) fs::remove_all(mRoot, ignored);
}

void SmallDisk::fill() const {
  std::FILE* file = std::fopen(path("filler").c_str(), "wb");
  if (!file) return;
  const std::vector<char> block(4096, 'x');
  while (std::fwrite(block.data(), 1, block.size(), file) == block.size() && std::fflush(file) == 0) {
  }
  std::fclose(file);
}

std::size_t SmallDisk::fileCount() const {
  return static_cast<std::size_t>(std::distance(fs::directory_iterator(mRoot), fs::directory_iterator()));
}

}  // namespace levelfuse::test
