// levelfuse: E57 scans as stations or as points (see E57Scans.h).

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/MemoryBudget.h>
#include <levelfuse/io/scans/E57Scans.h>
#include <levelfuse/io/scans/PointScans.h>

#include "E57Bytestreams.h"
#include "E57PagedFile.h"
#include "E57Xml.h"
#include "ScanDelivery.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>
#include <utility>

namespace levelfuse::io {

namespace {

using openvdb::Vec3d;

/// Records decoded between two questions to the interrupter.
constexpr std::uint64_t kRecordsPerCheck = 1 << 16;

/// Bytes held per grid cell or record while a scan is built and binned: its
/// point, intensity and colour, and its share of the range map.
constexpr double kBytesPerCell = 48.0;

/// A station's grid may have at most this many cells per record (and a few
/// more, kSpareCells): rays without a return (the sky, a doorway) leave
/// cells empty, but a grid mostly empty is not the scanner's.
constexpr double kMaxCellsPerRecord = 16.0;
constexpr double kSpareCells = 1024.0;

/// Where each field levelfuse reads sits among a scan's fields.
struct FieldPlaces {
  explicit FieldPlaces(const E57PointRecords& r)
      : x(r.find("cartesianX")), y(r.find("cartesianY")), z(r.find("cartesianZ")),
        range(r.find("sphericalRange")), azimuth(r.find("sphericalAzimuth")),
        elevation(r.find("sphericalElevation")), cartesianInvalid(r.find("cartesianInvalidState")),
        sphericalInvalid(r.find("sphericalInvalidState")), returnIndex(r.find("returnIndex")),
        row(r.find("rowIndex")), column(r.find("columnIndex")), intensity(r.find("intensity")),
        red(r.find("colorRed")), green(r.find("colorGreen")), blue(r.find("colorBlue")) {}
  bool cartesian() const { return x && y && z; }
  bool coloured() const { return red && green && blue; }
  bool structured() const { return row && column; }

  std::optional<std::size_t> x, y, z, range, azimuth, elevation, cartesianInvalid, sphericalInvalid, returnIndex,
      row, column, intensity, red, green, blue;
};

/// One record as levelfuse keeps it.
struct Return {
  Vec3d point;
  float intensity = 0.0f;
  Rgb8 colour;
};

/// An intensity as a float: beyond a float's range, or not a number, 0.
float intensityOf(double value) {
  return std::fabs(value) <= static_cast<double>(std::numeric_limits<float>::max()) ? static_cast<float>(value) : 0.0f;
}

/// Decodes the records of one scan.
class RecordDecoder {
 public:
  RecordDecoder(const E57ScanXml& xml, const E57Bytestreams& streams)
      : mXml(xml), mStreams(streams), mPlaces(xml.points) {}
  const FieldPlaces& places() const { return mPlaces; }

  /// The record's return, if it has one (a valid position, the first return).
  std::optional<Return> returnOf(std::uint64_t record) const {
    if (mPlaces.returnIndex && mStreams.integer(*mPlaces.returnIndex, record) != 0) return std::nullopt;
    const std::optional<std::size_t> invalid = mPlaces.cartesian() ? mPlaces.cartesianInvalid : mPlaces.sphericalInvalid;
    if (invalid && mStreams.integer(*invalid, record) != 0) return std::nullopt;
    Return r;
    r.point = mPlaces.cartesian() ? Vec3d(value(mPlaces.x, record), value(mPlaces.y, record), value(mPlaces.z, record))
                                  : sphericalPoint(record);
    if (!std::isfinite(r.point.x()) || !std::isfinite(r.point.y()) || !std::isfinite(r.point.z()) ||
        r.point == Vec3d(0.0))
      return std::nullopt;
    if (mPlaces.intensity) r.intensity = intensityOf(value(mPlaces.intensity, record));
    if (mPlaces.coloured())
      r.colour = Rgb8{channel(mPlaces.red, 0, record), channel(mPlaces.green, 1, record), channel(mPlaces.blue, 2, record)};
    return r;
  }

  /// The record's place among the grid's indices.
  std::int64_t index(const std::optional<std::size_t>& field, std::uint64_t record) const {
    return mXml.points.fields[*field].type == E57Field::Type::kFloat
               ? static_cast<std::int64_t>(std::llround(mStreams.value(*field, record)))
               : mStreams.integer(*field, record);
  }

 private:
  double value(const std::optional<std::size_t>& field, std::uint64_t record) const {
    return mStreams.value(*field, record);
  }
  Vec3d sphericalPoint(std::uint64_t record) const {
    const double r = value(mPlaces.range, record), a = value(mPlaces.azimuth, record),
                 e = value(mPlaces.elevation, record);
    return Vec3d(r * std::cos(e) * std::cos(a), r * std::cos(e) * std::sin(a), r * std::sin(e));
  }
  /// A colour channel scaled from the scan's colorLimits to 0 to 255.
  unsigned char channel(const std::optional<std::size_t>& field, int c, std::uint64_t record) const {
    const E57ColourRange& range = mXml.colourRanges[c];
    const double scaled = (value(field, record) - range.minimum) / (range.maximum - range.minimum) * 255.0;
    return static_cast<unsigned char>(std::lround(std::clamp(scaled, 0.0, 255.0)));
  }

  const E57ScanXml& mXml;
  const E57Bytestreams& mStreams;
  FieldPlaces mPlaces;
};

/// The span of the grid's indices along one direction: the indexBounds' if
/// given, else the records'.
E57IndexRange indexSpan(const std::optional<E57IndexRange>& bounds, const RecordDecoder& decoder,
                        const std::optional<std::size_t>& field, std::uint64_t records) {
  if (bounds) return *bounds;
  E57IndexRange span{std::numeric_limits<std::int64_t>::max(), std::numeric_limits<std::int64_t>::min()};
  for (std::uint64_t k = 0; k < records; ++k) {
    const std::int64_t i = decoder.index(field, k);
    span.minimum = std::min(span.minimum, i);
    span.maximum = std::max(span.maximum, i);
  }
  return span;
}

class ScanBuilder {
 public:
  ScanBuilder(const std::string& path, int index, const E57ScanXml& xml, const MemoryBudget& budget,
              const Interrupter& interrupter)
      : mPath(path), mWho(describeE57Scan(index, xml.name)), mXml(xml), mBudget(budget), mInterrupter(interrupter) {}

  E57Scan build(const E57Bytestreams& streams) const {
    const RecordDecoder decoder(mXml, streams);
    E57Scan scan;
    scan.records = mXml.points.recordCount;
    scan.station.scannerToWorld = mXml.pose;
    requireMemory(mBudget, mPath, static_cast<double>(scan.records) * kBytesPerCell,
                  "reading the " + std::to_string(scan.records) + " records of " + mWho,
                  "split the scan, or use a machine with more memory");
    if (decoder.places().structured()) placeOnGrid(decoder, scan.station);
    else gatherPoints(decoder, scan.station);
    if (scan.station.returns == 0)
      throw InputError(mPath, mWho + " has no returns: none of its " + std::to_string(scan.records) +
                                  " records holds a valid position");
    return scan;
  }

 private:
  /// The cells of a grid of these rows and columns, refused if it has more
  /// than kMaxCellsPerRecord per record, more than 2^31, or more than the
  /// memory budget holds.
  double checkedGridCells(const E57IndexRange& rows, const E57IndexRange& columns, std::uint64_t records) const {
    const double cells = (static_cast<double>(rows.maximum) - static_cast<double>(rows.minimum) + 1.0) *
                         (static_cast<double>(columns.maximum) - static_cast<double>(columns.minimum) + 1.0);
    const std::string grid = mWho + ": a grid of rows " + std::to_string(rows.minimum) + " to " +
                             std::to_string(rows.maximum) + " and columns " + std::to_string(columns.minimum) + " to " +
                             std::to_string(columns.maximum);
    if (cells > kMaxCellsPerRecord * static_cast<double>(records) + kSpareCells)
      throw InputError(mPath, grid + " has " + std::to_string(static_cast<long long>(cells)) + " cells for " +
                                  std::to_string(records) + " records, more than " +
                                  std::to_string(static_cast<int>(kMaxCellsPerRecord)) +
                                  " per record: its indexBounds or indices are not the scanner's grid");
    if (!(cells <= static_cast<double>(std::numeric_limits<int>::max())))
      throw InputError(mPath, grid + " has more than 2^31 cells");
    requireMemory(mBudget, mPath, cells * kBytesPerCell, mWho + "'s grid of " + std::to_string(static_cast<long long>(cells)) + " rays",
                  "split the scan, or use a machine with more memory");
    return cells;
  }

  void placeOnGrid(const RecordDecoder& decoder, StationGrid& station) const {
    const std::uint64_t records = mXml.points.recordCount;
    const FieldPlaces& places = decoder.places();
    const E57IndexRange rows = indexSpan(mXml.rows, decoder, places.row, records);
    const E57IndexRange columns = indexSpan(mXml.columns, decoder, places.column, records);
    const double cells = checkedGridCells(rows, columns, records);
    station.rows = static_cast<int>(rows.maximum - rows.minimum + 1);
    station.columns = static_cast<int>(columns.maximum - columns.minimum + 1);
    const std::size_t count = static_cast<std::size_t>(cells);
    station.points.assign(count, Vec3d(0.0));
    station.intensities.assign(count, 0.0f);
    if (places.coloured()) station.colours.assign(count, Rgb8{});
    for (std::uint64_t k = 0; k < records; ++k) {
      if (k % kRecordsPerCheck == 0) checkInterrupter(mInterrupter);
      const std::int64_t row = decoder.index(places.row, k), column = decoder.index(places.column, k);
      if (row < rows.minimum || row > rows.maximum || column < columns.minimum || column > columns.maximum)
        throw InputError(mPath, mWho + ": record " + std::to_string(k) + " has row " + std::to_string(row) +
                                    " and column " + std::to_string(column) + ", outside its grid's rows " +
                                    std::to_string(rows.minimum) + " to " + std::to_string(rows.maximum) +
                                    " and columns " + std::to_string(columns.minimum) + " to " +
                                    std::to_string(columns.maximum));
      const std::optional<Return> r = decoder.returnOf(k);
      if (!r) continue;
      const std::size_t cell = static_cast<std::size_t>(column - columns.minimum) * station.rows +
                               static_cast<std::size_t>(row - rows.minimum);
      const Vec3d& held = station.points[cell];
      if (held != Vec3d(0.0) && held.lengthSqr() <= r->point.lengthSqr()) continue;  // the nearer of two in a cell
      if (held == Vec3d(0.0)) ++station.returns;
      station.points[cell] = r->point;
      station.intensities[cell] = r->intensity;
      if (places.coloured()) station.colours[cell] = r->colour;
    }
  }

  void gatherPoints(const RecordDecoder& decoder, StationGrid& station) const {
    const std::uint64_t records = mXml.points.recordCount;
    const bool coloured = decoder.places().coloured();
    for (std::uint64_t k = 0; k < records; ++k) {
      if (k % kRecordsPerCheck == 0) checkInterrupter(mInterrupter);
      const std::optional<Return> r = decoder.returnOf(k);
      if (!r) continue;
      station.points.push_back(r->point);
      station.intensities.push_back(r->intensity);
      if (coloured) station.colours.push_back(r->colour);
    }
    station.returns = station.points.size();
  }

  const std::string& mPath;
  std::string mWho;
  const E57ScanXml& mXml;
  const MemoryBudget& mBudget;
  const Interrupter& mInterrupter;
};

std::string xmlSection(E57PagedFile& file) {
  std::string xml(static_cast<std::size_t>(file.header().xmlLogicalLength), '\0');
  file.read(file.logicalOffset(file.header().xmlPhysicalOffset, "the XML section"), xml.size(),
            reinterpret_cast<unsigned char*>(xml.data()), "the XML section");
  return xml;
}

}  // namespace

void readE57Scans(const std::string& path, const E57ScanTaker& take, const Interrupter& interrupter,
                  const MemoryBudget& budget) {
  E57PagedFile file(path);
  requireMemory(budget, path, static_cast<double>(file.header().xmlLogicalLength) * 4.0, "its XML section",
                "is this the right file?");
  const std::vector<E57ScanXml> scans = parseE57Xml(xmlSection(file), path);
  for (std::size_t i = 0; i < scans.size(); ++i) {
    checkInterrupter(interrupter);
    const int index = static_cast<int>(i + 1);
    const E57Bytestreams streams(file, scans[i].points, "the points of " + describeE57Scan(index, scans[i].name),
                                 budget, interrupter);
    E57Scan scan = ScanBuilder(path, index, scans[i], budget, interrupter).build(streams);
    scan.index = index;
    scan.name = scans[i].name;
    take(std::move(scan));
  }
}

RangeMap rangeMapFromE57Scan(const E57Scan& scan, double sigma, const std::string& path, const std::string& name) {
  if (scan.structured())
    return rangeMapFromStationGrid(scan.station, sigma, path, describeE57Scan(scan.index, scan.name), name);
  return rangeMapFromPointCloud(scan.station.points, scan.station.scannerToWorld, std::nullopt, sigma, path, name,
                                scan.station.colours);
}

std::vector<RangeMap> loadE57Scans(const std::string& path, const ScanLoadOptions& options) {
  const std::string stem = std::filesystem::path(path).stem().string();
  ScanDelivery scans(options);
  readE57Scans(
      path,
      [&](E57Scan&& scan) {
        const std::string name = scan.name.empty() ? stem + " scan " + std::to_string(scan.index) : scan.name;
        scans.offerAsRead(rangeMapFromE57Scan(scan, options.stationSigma, path, name), options.progress);
      },
      options.interrupter, options.memoryBudget);
  return scans.kept();
}

}  // namespace levelfuse::io
