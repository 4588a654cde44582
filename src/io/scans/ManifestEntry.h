// levelfuse: one entry of a JSON scan manifest, its fields read and checked
// (private to the manifest reader; the format is described in Manifest.h).
#pragma once

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/images/DepthImages.h>

#include <nlohmann/json.hpp>

#include <openvdb/math/Mat4.h>

#include <cmath>
#include <filesystem>
#include <initializer_list>
#include <stdexcept>
#include <string>
#include <vector>

namespace levelfuse::io {

/// An entry of a manifest's "scans": its fields, each checked as it is read,
/// and errors that name the manifest and the entry ("scans[2]: ...").
class Entry {
 public:
  using json = nlohmann::json;

  Entry(const std::string& manifest, const nlohmann::json& j, std::size_t index)
      : mManifest(manifest), mJson(j), mWhere("scans[" + std::to_string(index) + "]: ") {
    if (!j.is_object()) fail("expected an object");
  }

  [[noreturn]] void fail(const std::string& problem) const { throw InputError(mManifest, mWhere + problem); }
  /// What `make()` returns, or the entry's error with what it refused
  /// (std::invalid_argument: a scan's or a step's own checks).
  template <typename Make>
  auto checked(Make&& make) const -> decltype(make()) {
    try {
      return make();
    } catch (const std::invalid_argument& error) {
      fail(error.what());
    }
  }
  bool has(const char* key) const { return mJson.contains(key); }

  std::string string(const char* key) const {
    if (!has(key)) fail(std::string("missing '") + key + "'");
    if (!mJson[key].is_string()) fail(std::string("'") + key + "' must be a string");
    return mJson[key].get<std::string>();
  }
  /// The file a key names, resolved beside the manifest; it must exist.
  std::string path(const char* key) const {
    const std::string resolved = resolve(key);
    std::error_code ec;
    if (!std::filesystem::is_regular_file(resolved, ec)) fail(std::string("'") + key + "': no such file " + resolved);
    return resolved;
  }
  /// The folder a key names, resolved beside the manifest; it must exist.
  std::string folder(const char* key) const {
    const std::string resolved = resolve(key);
    std::error_code ec;
    if (!std::filesystem::is_directory(resolved, ec)) fail(std::string("'") + key + "': no such folder " + resolved);
    return resolved;
  }
  /// A JSON value that must be a finite number; `name` says which.
  double numberIn(const json& j, const std::string& name) const {
    if (!j.is_number()) fail(name + " must be a number");
    const double v = j.get<double>();
    if (!std::isfinite(v)) fail(name + " is not finite");
    return v;
  }
  double number(const char* key, double fallback) const {
    return has(key) ? numberIn(mJson[key], std::string("'") + key + "'") : fallback;
  }
  double positive(const char* key, double fallback) const {
    const double v = number(key, fallback);
    if (!(v > 0.0)) fail(std::string("'") + key + "' must be positive");
    return v;
  }
  std::vector<double> numbers(const json& j, const std::string& key, std::size_t count) const {
    if (!j.is_array() || j.size() != count)
      fail(quote(key) + " needs " + std::to_string(count) + " numbers");
    std::vector<double> v;
    for (const json& x : j) {
      if (!x.is_number() || !std::isfinite(x.get<double>())) fail(quote(key) + " holds something that is not a number");
      v.push_back(x.get<double>());
    }
    return v;
  }
  std::vector<double> numbers(const char* key, std::size_t count) const {
    if (!has(key)) fail(std::string("missing '") + key + "'");
    return numbers(mJson[key], key, count);
  }
  /// Fails naming the first field of the entry that is not one of `keys`
  /// (misspelt, or not one of its format's).
  void requireOnly(std::initializer_list<const char*> keys) const {
    for (const auto& item : mJson.items()) {
      bool known = false;
      std::string expected;
      for (const char* key : keys) {
        known = known || item.key() == key;
        expected += std::string(expected.empty() ? "" : ", ") + key;
      }
      if (!known) fail("unknown field " + quote(item.key()) + " for its format (expected " + expected + ")");
    }
  }
  const json& operator[](const char* key) const { return mJson[key]; }
  const std::string& where() const { return mWhere; }
  const std::string& manifest() const { return mManifest; }
  /// How many of `keys` the entry has.
  int countOf(std::initializer_list<const char*> keys) const {
    int count = 0;
    for (const char* key : keys) count += has(key) ? 1 : 0;
    return count;
  }

 private:
  std::string resolve(const char* key) const {
    const std::filesystem::path p(string(key));
    const std::filesystem::path beside = p.is_absolute() ? p : std::filesystem::path(mManifest).parent_path() / p;
    return beside.lexically_normal().string();
  }

  const std::string& mManifest;
  const json& mJson;
  std::string mWhere;
};

/// The entry's camera- (scanner-) to-world pose: its "pose_file", or its
/// "pose" of 16 numbers row by row (column vectors, translation in the last
/// column), in OpenVDB's row-vector layout.
inline openvdb::math::Mat4d poseOf(const Entry& e, const std::string& manifest) {
  if (e.has("pose_file")) return readPose(e.path("pose_file"));
  if (!e.has("pose")) e.fail("missing 'pose' or 'pose_file'");
  return poseFromRowMajor(e.numbers("pose", 16), manifest, e.where());
}

}  // namespace levelfuse::io
