// levelfuse: atomic output files.

#include <levelfuse/io/AtomicWrite.h>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace levelfuse::io {

namespace fs = std::filesystem;

namespace {

std::runtime_error cannotWrite(const std::string& path, const std::string& why) {
  return std::runtime_error("cannot write '" + path + "': " + why);
}

void requireReplaceable(const std::string& path) {
  std::error_code status;
  if (fs::exists(path, status) && !fs::is_regular_file(path, status))
    throw cannotWrite(path, "it exists and is not a regular file");
}

/// Flushes what the kernel holds of `path` (a file or a folder) to the disk.
/// Returns false with errno set if it could not.
bool syncToDisk(const std::string& path, bool folder) {
  const int fd = ::open(path.c_str(), (folder ? O_DIRECTORY : 0) | O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  const bool synced = ::fsync(fd) == 0 || errno == EINVAL;  // EINVAL: a file system that cannot sync
  ::close(fd);
  return synced;
}

std::string folderOf(const std::string& path) {
  const fs::path parent = fs::path(path).parent_path();
  return parent.empty() ? std::string(".") : parent.string();
}

void removeQuietly(const std::string& path) {
  std::error_code ignored;
  fs::remove(path, ignored);
}

}  // namespace

OutputSet::~OutputSet() { discard(); }

void OutputSet::discard() {
  for (const Entry& e : mEntries) removeQuietly(e.temporary);
  mEntries.clear();
}

std::vector<std::string> OutputSet::targets() const {
  std::vector<std::string> paths;
  for (const Entry& e : mEntries) paths.push_back(e.target);
  return paths;
}

void OutputSet::add(const std::string& path, const FileWriter& write) {
  requireReplaceable(path);
  std::error_code ec;
  for (const Entry& e : mEntries)
    if (e.target == path || fs::equivalent(e.target, path, ec))
      throw cannotWrite(path, "the run writes it twice");
  static std::atomic<unsigned> serial{0};
  const fs::path target(path);
  const std::string temporary = (target.parent_path() / ("." + target.filename().string() + ".tmp" +
                                                        std::to_string(::getpid()) + "-" +
                                                        std::to_string(serial++)))
                                    .string();
  try {
    write(temporary);
    if (!syncToDisk(temporary, false)) throw std::system_error(errno, std::generic_category());
  } catch (const std::exception& e) {
    removeQuietly(temporary);
    throw cannotWrite(path, e.what());
  }
  mEntries.push_back({path, temporary});
}

void OutputSet::commit() {
  std::vector<std::string> folders;
  for (std::size_t i = 0; i < mEntries.size(); ++i) {
    const Entry& e = mEntries[i];
    std::error_code ec;
    fs::rename(e.temporary, e.target, ec);
    if (ec) {
      mEntries.erase(mEntries.begin(), mEntries.begin() + static_cast<std::ptrdiff_t>(i));  // renamed already
      discard();
      throw cannotWrite(e.target, ec.message());
    }
    const std::string folder = folderOf(e.target);
    if (std::find(folders.begin(), folders.end(), folder) == folders.end()) folders.push_back(folder);
  }
  const std::vector<Entry> committed = std::move(mEntries);
  mEntries.clear();
  for (const std::string& folder : folders)  // the renames themselves survive a crash
    if (!syncToDisk(folder, true))
      throw std::runtime_error("cannot sync the folder '" + folder + "' after writing " + committed.front().target +
                               ": " + std::system_category().message(errno));
}

void closeChecked(std::ofstream& out) {
  out.flush();
  out.close();
  if (!out) throw std::runtime_error("write error (disk full?)");
}

void writeAtomically(const std::string& path, const FileWriter& write) {
  OutputSet outputs;
  outputs.add(path, write);
  outputs.commit();
}

void requireWritable(const std::string& path) {
  const fs::path target(path);
  if (target.filename().empty()) throw cannotWrite(path, "not a file name");
  const std::string folder = folderOf(path);
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) throw cannotWrite(path, "the folder '" + folder + "' does not exist");
  requireReplaceable(path);
  if (::access(folder.c_str(), W_OK) != 0) throw cannotWrite(path, "the folder '" + folder + "' is not writable");
}

}  // namespace levelfuse::io
