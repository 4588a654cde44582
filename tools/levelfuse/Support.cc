#include "Support.h"

#include <sys/resource.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <sstream>
#include <stdexcept>

namespace levelfuse::cli {

ThreadLimit::ThreadLimit(int threads) {
  if (threads > 0)
    mControl = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                     static_cast<std::size_t>(threads));
}

std::size_t peakResidentBytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<std::size_t>(usage.ru_maxrss) * 1024;  // kilobytes on Linux
}

void requireWritable(const std::string& path) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  if (target.filename().empty()) throw std::runtime_error("cannot write '" + path + "': not a file name");
  const fs::path folder = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    throw std::runtime_error("cannot write '" + path + "': the folder '" + folder.string() + "' does not exist");
  if (fs::exists(target, ec) && !fs::is_regular_file(target, ec))
    throw std::runtime_error("cannot write '" + path + "': it exists and is not a regular file");
  if (::access(folder.c_str(), W_OK) != 0)
    throw std::runtime_error("cannot write '" + path + "': the folder '" + folder.string() + "' is not writable");
}

std::string withCommas(std::size_t n) {
  std::string digits = std::to_string(n), out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

std::string fixed(double value, int digits) {
  std::ostringstream s;
  s.precision(digits);
  s << value;
  return s.str();
}

std::string printable(const std::string& text) {
  static const char kHex[] = "0123456789abcdef";
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte >= 0x20 && byte != 0x7f) {
      out += c;
    } else {
      out += "\\x";
      out += kHex[byte >> 4];
      out += kHex[byte & 15];
    }
  }
  return out;
}

std::string mebibytes(std::size_t bytes) { return fixed(static_cast<double>(bytes) / 1048576.0, 3) + " MiB"; }

openvdb::math::Vec3d parseVec3(const std::string& text) {
  std::vector<double> v;
  std::stringstream s(text);
  std::string item;
  while (std::getline(s, item, ',')) {
    std::size_t used = 0;
    double x = 0.0;
    try {
      x = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size() || !std::isfinite(x))
      throw std::invalid_argument("'" + text + "' is not three numbers x,y,z");
    v.push_back(x);
  }
  if (v.size() != 3) throw std::invalid_argument("'" + text + "' is not three numbers x,y,z");
  return openvdb::math::Vec3d(v[0], v[1], v[2]);
}

}  // namespace levelfuse::cli
