// levelfuse: checks before an input is opened, and the record of inputs.

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/InputFile.h>

#include <sys/stat.h>

#include <algorithm>
#include <mutex>
#include <stdexcept>

namespace levelfuse::io {

namespace {

std::mutex gInputsMutex;
std::vector<std::string> gInputs;

const char* kindOf(mode_t mode) {
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISCHR(mode) || S_ISBLK(mode)) return "a device";
  if (S_ISSOCK(mode)) return "a socket";
  if (S_ISDIR(mode)) return "a folder";
  return "not a regular file";
}

}  // namespace

void requireInputFile(const std::string& path, bool folderToo) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) throw InputError(path, "no such file");
  const bool accepted = S_ISREG(info.st_mode) || (folderToo && S_ISDIR(info.st_mode));
  if (!accepted)
    throw InputError(path, std::string("is ") + kindOf(info.st_mode) +
                               (folderToo ? ", not a file or folder levelfuse can read"
                                          : ", not a file levelfuse can read"));
  const std::lock_guard<std::mutex> lock(gInputsMutex);
  if (std::find(gInputs.begin(), gInputs.end(), path) == gInputs.end()) gInputs.push_back(path);
}

std::vector<std::string> inputsRead() {
  const std::lock_guard<std::mutex> lock(gInputsMutex);
  return gInputs;
}

void refuseOverwritingInputs(const std::vector<std::string>& outputs, const std::vector<std::string>& inputs) {
  for (const std::string& output : outputs) {
    struct stat out {};
    if (output.empty() || ::stat(output.c_str(), &out) != 0) continue;
    for (const std::string& input : inputs) {
      struct stat in {};
      if (::stat(input.c_str(), &in) == 0 && in.st_dev == out.st_dev && in.st_ino == out.st_ino)
        throw std::runtime_error("cannot write '" + output + "': it is an input of this run" +
                                 (input == output ? std::string() : " ('" + input + "')") +
                                 "; choose another name");
    }
  }
}

}  // namespace levelfuse::io
