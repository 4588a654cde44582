// libFuzzer targets: the fuzzer's bytes as files.

#include "FuzzInput.h"

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <unistd.h>

namespace levelfuse::fuzz {

namespace fs = std::filesystem;

namespace {

/// Created on first use; its destructor, run at exit, removes it.
class ScratchFolder {
 public:
  ScratchFolder() : mPath(fs::temp_directory_path() / ("levelfuse-fuzz-" + std::to_string(::getpid()))) {
    fs::create_directories(mPath);
  }
  ~ScratchFolder() {
    std::error_code ignored;
    fs::remove_all(mPath, ignored);
  }
  std::string path() const { return mPath.string(); }

 private:
  fs::path mPath;
};

}  // namespace

const std::string& scratchFolder() {
  static const ScratchFolder folder;
  static const std::string path = folder.path();
  return path;
}

std::string writeScratchFile(const std::string& name, const std::uint8_t* data, std::size_t size) {
  const std::string path = (fs::path(scratchFolder()) / name).string();
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  out.close();
  if (!out) throw std::runtime_error("cannot write " + path);
  return path;
}

std::string writeScratchFile(const std::string& name, const std::string& text) {
  return writeScratchFile(name, reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
}

}  // namespace levelfuse::fuzz
