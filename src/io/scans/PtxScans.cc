// levelfuse: PTX files as spherical range maps.

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/scans/PtxScans.h>

#include "../TextLineReader.h"
#include "PtxHeader.h"
#include "PtxPoints.h"
#include "ScanDelivery.h"

#include <filesystem>
#include <utility>

namespace levelfuse::io {

void readPtxScans(const std::string& path, const PtxScanTaker& take, const Interrupter& interrupter,
                  const MemoryBudget& budget) {
  TextLineReader lines(path);
  PtxHeader header, previous;
  for (bool first = true; readPtxHeader(lines, first ? nullptr : &previous, budget, header); first = false) {
    checkInterrupter(interrupter);
    take(readPtxPoints(lines, header, interrupter));
    previous = header;
  }
  if (previous.index == 0) throw InputError(path, "no scans: the file is empty or blank");
}

RangeMap rangeMapFromPtxScan(const PtxScan& scan, double sigma, const std::string& path, const std::string& name) {
  return rangeMapFromStationGrid(scan, sigma, path, describePtxScan(scan.index, scan.firstLine, scan.lastLine), name);
}

std::vector<RangeMap> loadPtxScans(const std::string& path, const ScanLoadOptions& options) {
  const std::string stem = std::filesystem::path(path).stem().string();
  ScanDelivery scans(options);
  readPtxScans(
      path,
      [&](PtxScan&& scan) {
        scans.offerAsRead(
            rangeMapFromPtxScan(scan, options.stationSigma, path, stem + " scan " + std::to_string(scan.index)),
            options.progress);
      },
      options.interrupter, options.memoryBudget);
  return scans.kept();
}

}  // namespace levelfuse::io
