// levelfuse: atomic output files.

#include <levelfuse/io/AtomicWrite.h>

#include <filesystem>
#include <stdexcept>
#include <system_error>
#include <unistd.h>

namespace levelfuse::io {

namespace fs = std::filesystem;

void writeAtomically(const std::string& path, const std::function<void(const std::string&)>& write) {
  const fs::path target(path);
  std::error_code status;
  if (fs::exists(target, status) && !fs::is_regular_file(target, status))
    throw std::runtime_error("cannot write '" + path + "': it exists and is not a regular file");
  const fs::path temporary =
      target.parent_path() / ("." + target.filename().string() + ".tmp" + std::to_string(::getpid()));
  const auto discard = [&] {
    std::error_code ignored;
    fs::remove(temporary, ignored);
  };
  try {
    write(temporary.string());
  } catch (const std::exception& e) {
    discard();
    throw std::runtime_error("cannot write '" + path + "': " + e.what());
  }
  std::error_code ec;
  fs::rename(temporary, target, ec);
  if (ec) {
    discard();
    throw std::runtime_error("cannot write '" + path + "': " + ec.message());
  }
}

}  // namespace levelfuse::io
