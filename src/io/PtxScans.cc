// levelfuse: PTX files as spherical range maps.

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/PtxScans.h>
#include <levelfuse/scan/SphericalScan.h>

#include "PtxGridChecks.h"
#include "PtxHeader.h"
#include "PtxPoints.h"
#include "ScanDelivery.h"
#include "TextLineReader.h"

#include <filesystem>
#include <stdexcept>
#include <utility>

namespace levelfuse::io {

void readPtxScans(const std::string& path, const PtxScanTaker& take, const Interrupter& interrupter) {
  TextLineReader lines(path);
  PtxHeader header, previous;
  for (bool first = true; readPtxHeader(lines, first ? nullptr : &previous, header); first = false) {
    checkInterrupter(interrupter);
    take(readPtxPoints(lines, header, interrupter));
    previous = header;
  }
  if (previous.index == 0) throw InputError(path, "no scans: the file is empty or blank");
}

RangeMap rangeMapFromPtxScan(const PtxScan& scan, double sigma, const std::string& path, const std::string& name) {
  try {
    const AngularSteps steps = stepsOfGrid(scan.points, scan.columns, scan.rows);
    requireGridOfTheScansSize(scan, steps, path);
    RangeMap map = sphericalMapFromPoints(scan.points, steps, scan.scannerToWorld, sigma, name, scan.colours);
    requireReturnsOnTheirOwnPixels(scan, map, path);
    return map;
  } catch (const std::invalid_argument& e) {  // the returns make no grid, or no map
    throw InputError(path, describePtxScan(scan.index, scan.firstLine, scan.lastLine) + ": " + e.what());
  }
}

std::vector<RangeMap> loadPtxScans(const std::string& path, const ScanLoadOptions& options) {
  const std::string stem = std::filesystem::path(path).stem().string();
  ScanDelivery scans(options);
  readPtxScans(
      path,
      [&](PtxScan&& scan) {
        scans.offer(rangeMapFromPtxScan(scan, options.ptxSigma, path, stem + " scan " + std::to_string(scan.index)));
        reportLoaded(options.progress, scans.delivered(), scans.delivered());
      },
      options.interrupter);
  return scans.kept();
}

}  // namespace levelfuse::io
