// E57 files for tests.

#include "E57Files.h"


#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace levelfuse::test {

namespace {

using openvdb::Vec3d;

constexpr std::size_t kPageData = 1020;

std::uint32_t crc32c(const unsigned char* data, std::size_t size) {
  std::uint32_t crc = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < size; ++i) {
    crc ^= data[i];
    for (int bit = 0; bit < 8; ++bit) crc = (crc >> 1) ^ ((crc & 1u) ? 0x82F63B78u : 0u);
  }
  return crc ^ 0xFFFFFFFFu;
}

void putLittle(std::vector<unsigned char>& out, std::uint64_t value, int bytes) {
  for (int i = 0; i < bytes; ++i) out.push_back(static_cast<unsigned char>(value >> (8 * i)));
}

void setLittle(std::vector<unsigned char>& out, std::size_t at, std::uint64_t value, int bytes) {
  for (int i = 0; i < bytes; ++i) out[at + i] = static_cast<unsigned char>(value >> (8 * i));
}

std::uint64_t physicalOf(std::uint64_t logical) { return logical / kPageData * 1024 + logical % kPageData; }

int bitsOf(const E57FieldSpec& f) {
  if (f.type == "Float") return f.single ? 32 : 64;
  const std::uint64_t span = static_cast<std::uint64_t>(f.maximum) - static_cast<std::uint64_t>(f.minimum);
  int bits = 0;
  while (bits < 64 && (span >> bits) != 0) ++bits;
  return bits;
}

/// The field's values bit-packed, least significant bit first.
std::vector<unsigned char> bytestream(const E57FieldSpec& f) {
  const int bits = bitsOf(f);
  std::vector<unsigned char> out((f.values.size() * static_cast<std::size_t>(bits) + 7) / 8, 0);
  for (std::size_t k = 0; k < f.values.size(); ++k) {
    std::uint64_t word = 0;
    if (f.type == "Float" && f.single) {
      const float v = static_cast<float>(f.values[k]);
      std::uint32_t w;
      std::memcpy(&w, &v, 4);
      word = w;
    } else if (f.type == "Float") {
      std::memcpy(&word, &f.values[k], 8);
    } else {
      word = static_cast<std::uint64_t>(static_cast<long long>(f.values[k])) - static_cast<std::uint64_t>(f.minimum);
    }
    for (int b = 0; b < bits; ++b)
      if ((word >> b) & 1u) {
        const std::size_t at = k * static_cast<std::size_t>(bits) + static_cast<std::size_t>(b);
        out[at / 8] |= static_cast<unsigned char>(1u << (at % 8));
      }
  }
  return out;
}

/// The scan's binary section, to start at logical offset `start`.
std::vector<unsigned char> binarySection(const E57ScanSpec& scan, std::uint64_t start) {
  std::vector<std::vector<unsigned char>> streams;
  for (const E57FieldSpec& f : scan.fields) streams.push_back(bytestream(f));
  std::vector<unsigned char> section;
  section.push_back(1);  // a compressed vector
  section.insert(section.end(), 7, 0);
  putLittle(section, 0, 8);  // its length, set below
  putLittle(section, physicalOf(start + 32), 8);
  putLittle(section, 0, 8);  // no index packet
  const std::size_t packets = std::max<std::size_t>(1, scan.packets);
  for (std::size_t p = 0; p < packets; ++p) {
    std::vector<std::pair<std::size_t, std::size_t>> parts;  // each stream's bytes in this packet
    std::size_t payload = 0;
    for (const auto& s : streams) {
      const std::size_t chunk = (s.size() + packets - 1) / packets;
      const std::size_t from = std::min(s.size(), p * chunk), to = std::min(s.size(), (p + 1) * chunk);
      parts.emplace_back(from, to);
      payload += to - from;
    }
    const std::size_t length = 6 + 2 * streams.size() + payload;
    if (length > 65536) throw std::invalid_argument("writeE57: a packet over 64 KiB; use more packets");
    section.push_back(static_cast<unsigned char>(scan.packetType));
    section.push_back(0);
    putLittle(section, length - 1, 2);
    putLittle(section, streams.size(), 2);
    for (const auto& [from, to] : parts) putLittle(section, to - from, 2);
    for (std::size_t i = 0; i < streams.size(); ++i)
      section.insert(section.end(), streams[i].begin() + static_cast<std::ptrdiff_t>(parts[i].first),
                     streams[i].begin() + static_cast<std::ptrdiff_t>(parts[i].second));
  }
  setLittle(section, 8, section.size(), 8);
  return section;
}

std::string number(double x) {
  char text[40];
  std::snprintf(text, sizeof(text), "%.17g", x);
  return text;
}

std::string fieldXml(const E57FieldSpec& f) {
  std::string xml = "<" + f.name + " type=\"" + f.type + "\"";
  if (f.type == "Float") xml += std::string(" precision=\"") + (f.single ? "single" : "double") + "\"";
  else xml += " minimum=\"" + std::to_string(f.minimum) + "\" maximum=\"" + std::to_string(f.maximum) + "\"";
  if (f.type == "ScaledInteger") xml += " scale=\"" + number(f.scale) + "\" offset=\"" + number(f.offset) + "\"";
  return xml + "/>";
}

std::string scanXml(const E57ScanSpec& scan, std::uint64_t physicalOffset) {
  std::ostringstream xml;
  const std::uint64_t records = scan.declaredRecords ? *scan.declaredRecords
                                                     : (scan.fields.empty() ? 0 : scan.fields[0].values.size());
  xml << "<vectorChild type=\"Structure\">\n";
  if (!scan.name.empty()) xml << "<name type=\"String\"><![CDATA[" << scan.name << "]]></name>\n";
  if (scan.rotation) {
    const auto& q = *scan.rotation;
    xml << "<pose type=\"Structure\"><rotation type=\"Structure\"><w type=\"Float\">" << number(q[0])
        << "</w><x type=\"Float\">" << number(q[1]) << "</x><y type=\"Float\">" << number(q[2])
        << "</y><z type=\"Float\">" << number(q[3]) << "</z></rotation><translation type=\"Structure\"><x type=\"Float\">"
        << number(scan.translation[0]) << "</x><y type=\"Float\">" << number(scan.translation[1])
        << "</y><z type=\"Float\">" << number(scan.translation[2]) << "</z></translation></pose>\n";
  }
  if (scan.indexBounds) {
    const auto& b = *scan.indexBounds;
    xml << "<indexBounds type=\"Structure\"><rowMinimum type=\"Integer\">" << b[0]
        << "</rowMinimum><rowMaximum type=\"Integer\">" << b[1] << "</rowMaximum><columnMinimum type=\"Integer\">"
        << b[2] << "</columnMinimum><columnMaximum type=\"Integer\">" << b[3] << "</columnMaximum></indexBounds>\n";
  }
  xml << "<points type=\"CompressedVector\" fileOffset=\"" << physicalOffset << "\" recordCount=\"" << records
      << "\">\n<prototype type=\"Structure\">\n";
  for (const E57FieldSpec& f : scan.fields) xml << fieldXml(f) << "\n";
  xml << "</prototype>\n<codecs type=\"Vector\" allowHeterogeneousChildren=\"1\">" << scan.codecs
      << "</codecs>\n</points>\n</vectorChild>\n";
  return xml.str();
}

/// The scanner's pose as E57 writes it: a unit quaternion (of the rotation
/// world = R p, column vectors) and a translation.
void setPose(E57ScanSpec& scan, const openvdb::math::Mat4d& scannerToWorld) {
  double r[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r[i][j] = scannerToWorld[j][i];  // row-vector layout: row j is axis j
  double w, x, y, z;
  const double trace = r[0][0] + r[1][1] + r[2][2];
  if (trace > 0.0) {
    const double s = 2.0 * std::sqrt(1.0 + trace);
    w = 0.25 * s, x = (r[2][1] - r[1][2]) / s, y = (r[0][2] - r[2][0]) / s, z = (r[1][0] - r[0][1]) / s;
  } else if (r[0][0] > r[1][1] && r[0][0] > r[2][2]) {
    const double s = 2.0 * std::sqrt(1.0 + r[0][0] - r[1][1] - r[2][2]);
    w = (r[2][1] - r[1][2]) / s, x = 0.25 * s, y = (r[0][1] + r[1][0]) / s, z = (r[0][2] + r[2][0]) / s;
  } else if (r[1][1] > r[2][2]) {
    const double s = 2.0 * std::sqrt(1.0 + r[1][1] - r[0][0] - r[2][2]);
    w = (r[0][2] - r[2][0]) / s, x = (r[0][1] + r[1][0]) / s, y = 0.25 * s, z = (r[1][2] + r[2][1]) / s;
  } else {
    const double s = 2.0 * std::sqrt(1.0 + r[2][2] - r[0][0] - r[1][1]);
    w = (r[1][0] - r[0][1]) / s, x = (r[0][2] + r[2][0]) / s, y = (r[1][2] + r[2][1]) / s, z = 0.25 * s;
  }
  scan.rotation = std::array<double, 4>{w, x, y, z};
  const Vec3d t = scannerToWorld.getTranslation();
  scan.translation = {t.x(), t.y(), t.z()};
}

E57FieldSpec integerField(const std::string& name, long long minimum, long long maximum) {
  E57FieldSpec f;
  f.name = name;
  f.type = "Integer";
  f.minimum = minimum;
  f.maximum = maximum;
  return f;
}

}  // namespace

void writeE57(const std::string& path, const std::vector<E57ScanSpec>& scans,
              const std::function<void(std::string&)>& editXml) {
  std::vector<unsigned char> logical(48, 0);
  std::string xml =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<e57Root type=\"Structure\" "
      "xmlns=\"http://www.astm.org/COMMIT/E57/2010-e57-v1.0\">\n<formatName type=\"String\"><![CDATA[ASTM E57 3D "
      "Imaging Data File]]></formatName>\n<data3D type=\"Vector\" allowHeterogeneousChildren=\"1\">\n";
  for (const E57ScanSpec& scan : scans) {
    const std::uint64_t start = logical.size();
    const std::vector<unsigned char> section = binarySection(scan, start);
    logical.insert(logical.end(), section.begin(), section.end());
    xml += scanXml(scan, physicalOf(start));
  }
  xml += "</data3D>\n</e57Root>\n";
  if (editXml) editXml(xml);
  const std::uint64_t xmlStart = logical.size();
  logical.insert(logical.end(), xml.begin(), xml.end());
  logical.resize((logical.size() + kPageData - 1) / kPageData * kPageData, 0);
  const std::uint64_t pages = logical.size() / kPageData;
  std::memcpy(logical.data(), "ASTM-E57", 8);
  setLittle(logical, 8, 1, 4);
  setLittle(logical, 12, 0, 4);
  setLittle(logical, 16, pages * 1024, 8);
  setLittle(logical, 24, physicalOf(xmlStart), 8);
  setLittle(logical, 32, xml.size(), 8);
  setLittle(logical, 40, 1024, 8);
  std::ofstream out(path, std::ios::binary);
  for (std::uint64_t p = 0; p < pages; ++p) {
    const unsigned char* page = logical.data() + p * kPageData;
    const std::uint32_t crc = crc32c(page, kPageData);
    const unsigned char stored[4] = {static_cast<unsigned char>(crc >> 24), static_cast<unsigned char>(crc >> 16),
                                     static_cast<unsigned char>(crc >> 8), static_cast<unsigned char>(crc)};
    out.write(reinterpret_cast<const char*>(page), kPageData);
    out.write(reinterpret_cast<const char*>(stored), 4);
  }
  if (!out) throw std::runtime_error("writeE57: cannot write " + path);
}

E57ScanSpec stationScan(const PtxGrid& grid, const RangeAlong& range, const std::string& name,
                        const std::vector<Rgb8>& colours) {
  const std::vector<Vec3d> points = scanPoints(grid, range);
  E57ScanSpec scan;
  scan.name = name;
  setPose(scan, grid.scannerToWorld);
  scan.indexBounds = std::array<long long, 4>{0, grid.rows - 1, 0, grid.columns - 1};
  const char* axes[3] = {"cartesianX", "cartesianY", "cartesianZ"};
  for (int a = 0; a < 3; ++a) {
    E57FieldSpec f;
    f.name = axes[a];
    f.type = "ScaledInteger";
    f.minimum = -8388608;
    f.maximum = 8388607;
    f.scale = 1e-4;
    scan.fields.push_back(f);
  }
  E57FieldSpec intensity = integerField("intensity", 0, 2047);
  E57FieldSpec row = integerField("rowIndex", 0, 4095), column = integerField("columnIndex", 0, 4095);
  E57FieldSpec invalid = integerField("cartesianInvalidState", 0, 2);
  std::vector<E57FieldSpec> rgb;
  if (!colours.empty())
    for (const char* c : {"colorRed", "colorGreen", "colorBlue"}) rgb.push_back(integerField(c, 0, 255));
  for (int c = 0; c < grid.columns; ++c)
    for (int r = 0; r < grid.rows; ++r) {
      const std::size_t i = static_cast<std::size_t>(c) * grid.rows + r;
      const bool hit = points[i] != Vec3d(0.0);
      for (int a = 0; a < 3; ++a) scan.fields[a].values.push_back(std::round(points[i][a] / 1e-4));
      intensity.values.push_back(static_cast<double>((c * 7 + r) % 2048));
      row.values.push_back(r);
      column.values.push_back(c);
      invalid.values.push_back(hit ? 0 : 2);
      if (!colours.empty()) {
        rgb[0].values.push_back(colours[i][0]);
        rgb[1].values.push_back(colours[i][1]);
        rgb[2].values.push_back(colours[i][2]);
      }
    }
  scan.fields.push_back(intensity);
  scan.fields.insert(scan.fields.end(), rgb.begin(), rgb.end());
  scan.fields.push_back(row);
  scan.fields.push_back(column);
  scan.fields.push_back(invalid);
  return scan;
}

E57ScanSpec sphericalStationScan(const PtxGrid& grid, const RangeAlong& range, const std::string& name) {
  E57ScanSpec scan;
  scan.name = name;
  setPose(scan, grid.scannerToWorld);
  E57FieldSpec r, azimuth, elevation;
  r.name = "sphericalRange";
  azimuth.name = "sphericalAzimuth";
  elevation.name = "sphericalElevation";
  E57FieldSpec row = integerField("rowIndex", 0, 4095), column = integerField("columnIndex", 0, 4095);
  E57FieldSpec invalid = integerField("sphericalInvalidState", 0, 2);
  for (int c = 0; c < grid.columns; ++c)
    for (int k = 0; k < grid.rows; ++k) {
      const Vec3d ray = ptxRay(grid, c, k);
      const double distance = range(ray);
      r.values.push_back(distance > 0.0 ? distance : 0.0);
      azimuth.values.push_back(std::atan2(ray.y(), ray.x()));
      elevation.values.push_back(std::asin(std::clamp(ray.z(), -1.0, 1.0)));
      row.values.push_back(k);
      column.values.push_back(c);
      invalid.values.push_back(distance > 0.0 ? 0 : 1);
    }
  scan.fields = {r, azimuth, elevation, row, column, invalid};
  return scan;
}

void flipByte(const std::string& path, std::uint64_t offset) {
  std::fstream file(path, std::ios::in | std::ios::out | std::ios::binary);
  file.seekg(static_cast<std::streamoff>(offset));
  char byte = 0;
  file.read(&byte, 1);
  byte = static_cast<char>(~byte);
  file.seekp(static_cast<std::streamoff>(offset));
  file.write(&byte, 1);
}

}  // namespace levelfuse::test
