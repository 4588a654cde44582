// levelfuse: an E57 file's XML section, read with pugixml.

#include "E57Xml.h"

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/TextRecords.h>

#include <pugixml.hpp>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>

namespace levelfuse::io {

namespace {

using Type = E57Field::Type;

/// Refusals about one scan of one file: "scan 1 ('pumpA'): ...".
class ScanContext {
 public:
  ScanContext(const std::string& path, std::size_t index, const std::string& name)
      : mPath(path), mWho(describeE57Scan(static_cast<int>(index + 1), name)) {}
  [[noreturn]] void fail(const std::string& problem) const { throw InputError(mPath, mWho + ": " + problem); }
  const std::string& path() const { return mPath; }
  /// "scan 1 ('pumpA'): ", the start of a message about it.
  std::string at() const { return mWho + ": "; }

 private:
  const std::string& mPath;
  std::string mWho;
};

std::string trimmed(const char* text) {
  std::string s(text);
  const auto first = s.find_first_not_of(" \t\r\n");
  if (first == std::string::npos) return {};
  return s.substr(first, s.find_last_not_of(" \t\r\n") - first + 1);
}

/// A whole number written in the XML ("" is 0, E57's default).
std::int64_t integerOf(const char* text, const std::string& what, const ScanContext& scan) {
  const std::string s = trimmed(text);
  if (s.empty()) return 0;
  errno = 0;
  char* end = nullptr;
  const long long value = std::strtoll(s.c_str(), &end, 10);
  if (end != s.c_str() + s.size()) scan.fail(what + " is " + quote(s) + ", not a whole number");
  if (errno == ERANGE) scan.fail(what + " is " + quote(s) + ", beyond a 64-bit integer");
  return value;
}

std::uint64_t countOf(const char* text, const std::string& what, const ScanContext& scan) {
  const std::string s = trimmed(text);
  if (s.empty() || s[0] == '-') scan.fail(what + " is " + quote(s) + ", not a count");
  errno = 0;
  char* end = nullptr;
  const unsigned long long value = std::strtoull(s.c_str(), &end, 10);
  if (end != s.c_str() + s.size()) scan.fail(what + " is " + quote(s) + ", not a count");
  if (errno == ERANGE) scan.fail(what + " is " + quote(s) + ", beyond a 64-bit count");
  return value;
}

double realOf(const char* text, const std::string& what, const ScanContext& scan) {
  const std::string s = trimmed(text);
  return s.empty() ? 0.0 : finiteNumber(s, scan.path(), scan.at() + what + ": ");
}

std::string typeOf(const pugi::xml_node& node) { return node.attribute("type").value(); }

/// The value of an element of type Integer, ScaledInteger or Float.
double numberOf(const pugi::xml_node& node, const std::string& what, const ScanContext& scan) {
  const std::string type = typeOf(node);
  if (type == "Float") return realOf(node.child_value(), what, scan);
  if (type == "Integer") return static_cast<double>(integerOf(node.child_value(), what, scan));
  if (type == "ScaledInteger") {
    const double scale = node.attribute("scale") ? realOf(node.attribute("scale").value(), what + "'s scale", scan) : 1.0;
    const double offset =
        node.attribute("offset") ? realOf(node.attribute("offset").value(), what + "'s offset", scan) : 0.0;
    return static_cast<double>(integerOf(node.child_value(), what, scan)) * scale + offset;
  }
  scan.fail(what + " is of type " + quote(type) + ", not a number");
}

/// The number of the child `name` of `parent`, or `missing` if it has none.
double numberOrDefault(const pugi::xml_node& parent, const char* name, double missing, const ScanContext& scan) {
  const pugi::xml_node node = parent.child(name);
  return node ? numberOf(node, quote(name), scan) : missing;
}

std::int64_t integerAttribute(const pugi::xml_node& node, const char* name, std::int64_t missing,
                              const std::string& what, const ScanContext& scan) {
  const pugi::xml_attribute a = node.attribute(name);
  return a ? integerOf(a.value(), what + "'s " + name, scan) : missing;
}

E57Field fieldOf(const pugi::xml_node& node, const std::string& name, const ScanContext& scan) {
  const std::string what = "the field " + quote(name);
  const std::string type = typeOf(node);
  E57Field f;
  f.name = name;
  if (type == "Float") {
    const std::string precision = node.attribute("precision") ? node.attribute("precision").value() : "double";
    if (precision != "single" && precision != "double")
      scan.fail(what + " has precision " + quote(precision) + " (expected single or double)");
    f.type = Type::kFloat;
    f.doublePrecision = precision == "double";
    return f;
  }
  if (type != "Integer" && type != "ScaledInteger")
    scan.fail(what + " is of type " + quote(type) + ", which levelfuse does not read in points");
  f.type = type == "Integer" ? Type::kInteger : Type::kScaledInteger;
  f.minimum = integerAttribute(node, "minimum", std::numeric_limits<std::int64_t>::min(), what, scan);
  f.maximum = integerAttribute(node, "maximum", std::numeric_limits<std::int64_t>::max(), what, scan);
  if (f.minimum > f.maximum)
    scan.fail(what + " has minimum " + std::to_string(f.minimum) + " above its maximum " + std::to_string(f.maximum));
  if (f.type == Type::kScaledInteger) {
    f.scale = node.attribute("scale") ? realOf(node.attribute("scale").value(), what + "'s scale", scan) : 1.0;
    f.offset = node.attribute("offset") ? realOf(node.attribute("offset").value(), what + "'s offset", scan) : 0.0;
    if (f.scale == 0.0) scan.fail(what + " has a scale of 0");
  }
  return f;
}

/// The prototype's terminal fields depth first, the bytestreams' order.
void collectFields(const pugi::xml_node& structure, const std::string& prefix, std::vector<E57Field>& fields,
                   const ScanContext& scan) {
  for (const pugi::xml_node& child : structure.children()) {
    if (child.type() != pugi::node_element) continue;
    const std::string name = prefix + child.name();
    if (typeOf(child) == "Structure") collectFields(child, name + "/", fields, scan);
    else fields.push_back(fieldOf(child, name, scan));
  }
}

E57PointRecords pointsOf(const pugi::xml_node& scanNode, const ScanContext& scan) {
  const pugi::xml_node points = scanNode.child("points");
  if (!points) scan.fail("no 'points'");
  if (typeOf(points) != "CompressedVector")
    scan.fail("its 'points' are of type " + quote(typeOf(points)) + ", not a CompressedVector");
  E57PointRecords r;
  if (!points.attribute("fileOffset")) scan.fail("its 'points' have no fileOffset");
  if (!points.attribute("recordCount")) scan.fail("its 'points' have no recordCount");
  r.fileOffset = countOf(points.attribute("fileOffset").value(), "the points' fileOffset", scan);
  r.recordCount = countOf(points.attribute("recordCount").value(), "the points' recordCount", scan);
  const pugi::xml_node prototype = points.child("prototype");
  if (!prototype) scan.fail("its 'points' have no prototype");
  collectFields(prototype, "", r.fields, scan);
  if (r.fields.empty()) scan.fail("its points' prototype has no fields");
  for (const pugi::xml_node& codec : points.child("codecs").children())
    if (codec.type() == pugi::node_element)
      scan.fail("its points name a codec (" + quote(codec.name()) +
                "); levelfuse reads E57's default, bit packing, alone");
  const bool cartesian = r.find("cartesianX") && r.find("cartesianY") && r.find("cartesianZ");
  const bool spherical = r.find("sphericalRange") && r.find("sphericalAzimuth") && r.find("sphericalElevation");
  if (!cartesian && !spherical)
    scan.fail("its points have neither cartesianX, Y and Z nor sphericalRange, Azimuth and Elevation");
  return r;
}

/// How far from 1 the norm of a pose's quaternion may be (values written to a
/// few digits).
constexpr double kQuaternionTolerance = 1e-3;

/// The scan's pose: world = R x + t with R the unit quaternion `rotation`.
openvdb::math::Mat4d poseOf(const pugi::xml_node& scanNode, const ScanContext& scan) {
  const pugi::xml_node pose = scanNode.child("pose");
  if (!pose) return openvdb::math::Mat4d::identity();
  const pugi::xml_node rotation = pose.child("rotation"), translation = pose.child("translation");
  double w = 1.0, x = 0.0, y = 0.0, z = 0.0;
  if (rotation) {
    w = numberOrDefault(rotation, "w", 0.0, scan);
    x = numberOrDefault(rotation, "x", 0.0, scan);
    y = numberOrDefault(rotation, "y", 0.0, scan);
    z = numberOrDefault(rotation, "z", 0.0, scan);
  }
  const openvdb::math::Vec3d t(numberOrDefault(translation, "x", 0.0, scan), numberOrDefault(translation, "y", 0.0, scan),
                               numberOrDefault(translation, "z", 0.0, scan));
  return rigidMotion(unitQuaternion(x, y, z, w, scan.path(), scan.at() + "its pose's rotation: ", kQuaternionTolerance),
                     t);
}

/// A grid index the indexBounds give, a whole number of at most 2^40 either way.
std::int64_t indexOf(double value, const char* name, const ScanContext& scan) {
  constexpr double kLargestIndex = 1099511627776.0;
  if (!(std::fabs(value) <= kLargestIndex) || value != std::floor(value))
    scan.fail(std::string("its indexBounds give ") + name + " " + std::to_string(value) +
              ", not a whole number within 2^40");
  return static_cast<std::int64_t>(value);
}

std::optional<E57IndexRange> indexRangeOf(const pugi::xml_node& bounds, const char* minimum, const char* maximum,
                                          const ScanContext& scan) {
  if (!bounds || !bounds.child(maximum)) return std::nullopt;
  E57IndexRange range;
  range.minimum = indexOf(numberOrDefault(bounds, minimum, 0.0, scan), minimum, scan);
  range.maximum = indexOf(numberOrDefault(bounds, maximum, 0.0, scan), maximum, scan);
  if (range.minimum > range.maximum)
    scan.fail(std::string("its indexBounds give ") + minimum + " " + std::to_string(range.minimum) + " above " +
              maximum + " " + std::to_string(range.maximum));
  return range;
}

void colourRangesOf(const pugi::xml_node& scanNode, E57ColourRange (&ranges)[3], const ScanContext& scan) {
  const pugi::xml_node limits = scanNode.child("colorLimits");
  if (!limits) return;
  const char* names[3][2] = {{"colorRedMinimum", "colorRedMaximum"},
                             {"colorGreenMinimum", "colorGreenMaximum"},
                             {"colorBlueMinimum", "colorBlueMaximum"}};
  for (int c = 0; c < 3; ++c) {
    ranges[c].minimum = numberOrDefault(limits, names[c][0], 0.0, scan);
    ranges[c].maximum = numberOrDefault(limits, names[c][1], 255.0, scan);
    if (!(ranges[c].maximum > ranges[c].minimum))
      scan.fail(std::string("its colorLimits give ") + names[c][1] + " " + std::to_string(ranges[c].maximum) +
                ", not above " + names[c][0] + " " + std::to_string(ranges[c].minimum));
  }
}

}  // namespace

std::string describeE57Scan(int index, const std::string& name) {
  return "scan " + std::to_string(index) + (name.empty() ? "" : " (" + quote(name) + ")");
}

int E57Field::bits() const {
  if (type == Type::kFloat) return doublePrecision ? 64 : 32;
  const std::uint64_t span = static_cast<std::uint64_t>(maximum) - static_cast<std::uint64_t>(minimum);
  int bits = 0;
  while (bits < 64 && (span >> bits) != 0) ++bits;
  return bits;
}

std::optional<std::size_t> E57PointRecords::find(const std::string& name) const {
  for (std::size_t i = 0; i < fields.size(); ++i)
    if (fields[i].name == name) return i;
  return std::nullopt;
}

std::vector<E57ScanXml> parseE57Xml(const std::string& xml, const std::string& path) {
  pugi::xml_document document;
  const pugi::xml_parse_result parsed = document.load_buffer(xml.data(), xml.size());
  if (!parsed)
    throw InputError(path, std::string("its XML section does not parse: ") + parsed.description() + " at byte " +
                               std::to_string(parsed.offset) + " of " + std::to_string(xml.size()));
  const pugi::xml_node root = document.child("e57Root");
  if (!root) throw InputError(path, "its XML section has no e57Root: not an E57 file?");
  std::vector<E57ScanXml> scans;
  for (const pugi::xml_node& node : root.child("data3D").children()) {
    if (node.type() != pugi::node_element) continue;
    const std::string name = trimmed(node.child("name").child_value());
    const ScanContext scan(path, scans.size(), name);
    if (typeOf(node) != "Structure") scan.fail("is of type " + quote(typeOf(node)) + ", not a Structure");
    E57ScanXml s;
    s.name = name;
    s.pose = poseOf(node, scan);
    const pugi::xml_node bounds = node.child("indexBounds");
    s.rows = indexRangeOf(bounds, "rowMinimum", "rowMaximum", scan);
    s.columns = indexRangeOf(bounds, "columnMinimum", "columnMaximum", scan);
    colourRangesOf(node, s.colourRanges, scan);
    s.points = pointsOf(node, scan);
    scans.push_back(std::move(s));
  }
  if (scans.empty()) throw InputError(path, "holds no 3D scans (its data3D is empty or missing): images alone?");
  return scans;
}

}  // namespace levelfuse::io
