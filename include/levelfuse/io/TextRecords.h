// levelfuse: line-oriented text files of whitespace-separated words, with
// '#' comments, as the Stanford .conf and the TUM RGB-D lists are; and the
// poses they write as a translation and a unit quaternion.
#pragma once

#include <openvdb/math/Mat4.h>
#include <openvdb/math/Quat.h>
#include <openvdb/Types.h>

#include <functional>
#include <sstream>
#include <string>

namespace levelfuse::io {

/// Calls `onRecord(line, at, words)` for every line of `path` that holds a
/// word and whose first word does not start with '#'; `at` is "line N: ", for
/// messages.
/// Throws InputError if the file is missing or unreadable.
void forEachTextRecord(const std::string& path,
                       const std::function<void(int line, const std::string& at, std::istringstream& words)>& onRecord);

/// `word` as a finite number; InputError naming `path` and `at` otherwise.
double finiteNumber(const std::string& word, const std::string& path, const std::string& at);

/// The next word of `words` as a finite number; InputError with `expected`
/// (what the line should hold) if the line has no more words.
double nextNumber(std::istringstream& words, const std::string& path, const std::string& at,
                  const std::string& expected);

/// The rotation (x, y, z, w), normalised; InputError naming `path` and `at` for a
/// zero quaternion or one whose norm is off 1 by more than `tolerance` (a scaled
/// or corrupted rotation).
openvdb::math::Quatd unitQuaternion(double x, double y, double z, double w, const std::string& path,
                                    const std::string& at, double tolerance = 1e-3);

/// p -> R(q) p + t (column vectors) in OpenVDB's row-vector layout; q a unit quaternion.
openvdb::math::Mat4d rigidMotion(const openvdb::math::Quatd& rotation, const openvdb::Vec3d& translation);

}  // namespace levelfuse::io
