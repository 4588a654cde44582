// levelfuse: line-oriented text records and their poses.

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/InputFile.h>
#include <levelfuse/io/TextRecords.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace levelfuse::io {

void forEachTextRecord(
    const std::string& path,
    const std::function<void(int line, const std::string& at, std::istringstream& words)>& onRecord) {
  requireInputFile(path);
  std::ifstream in(path);
  std::error_code ec;  // the non-throwing overload: a name may be too long
  if (!in) throw InputError(path, std::filesystem::exists(path, ec) ? "cannot be opened for reading" : "no such file");
  std::string line;
  for (int lineNo = 1; std::getline(in, line); ++lineNo) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream words(line);
    std::string first;
    if (!(words >> first) || first[0] == '#') continue;
    words.clear();
    words.seekg(0);
    onRecord(lineNo, "line " + std::to_string(lineNo) + ": ", words);
  }
}

double finiteNumber(const std::string& word, const std::string& path, const std::string& at) {
  char* end = nullptr;
  const double x = std::strtod(word.c_str(), &end);
  if (word.empty() || end != word.c_str() + word.size()) throw InputError(path, at + quote(word) + " is not a number");
  if (!std::isfinite(x)) throw InputError(path, at + quote(word) + " is not a finite number");
  return x;
}

double nextNumber(std::istringstream& words, const std::string& path, const std::string& at,
                  const std::string& expected) {
  std::string word;
  if (!(words >> word)) throw InputError(path, at + "expected " + expected);
  return finiteNumber(word, path, at);
}

openvdb::math::Quatd unitQuaternion(double x, double y, double z, double w, const std::string& path,
                                    const std::string& at, double tolerance) {
  const double norm = std::sqrt(x * x + y * y + z * z + w * w);
  if (norm < 1e-9) throw InputError(path, at + "the quaternion is zero: it describes no rotation");
  if (!(std::fabs(norm - 1.0) <= tolerance))
    throw InputError(path, at + "the quaternion has norm " + std::to_string(norm) + ", not 1: not a rotation");
  return openvdb::math::Quatd(x / norm, y / norm, z / norm, w / norm);
}

openvdb::math::Mat4d rigidMotion(const openvdb::math::Quatd& rotation, const openvdb::Vec3d& translation) {
  const double x = rotation.x(), y = rotation.y(), z = rotation.z(), w = rotation.w();
  // R of the unit quaternion (column-vector convention).
  const double r[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
                          {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
                          {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}};
  // OpenVDB's row vectors: p_world = p R^T + t, the transpose of R in the 3x3 block.
  return openvdb::math::Mat4d(r[0][0], r[1][0], r[2][0], 0.0, r[0][1], r[1][1], r[2][1], 0.0, r[0][2], r[1][2],
                              r[2][2], 0.0, translation.x(), translation.y(), translation.z(), 1.0);
}

}  // namespace levelfuse::io
