// levelfuse: the point lines of a PTX scan, read and checked (private to the
// PTX reader; the format is described in PtxScans.h).
#pragma once

#include "../TextLineReader.h"
#include "PtxHeader.h"

#include <levelfuse/core/Interrupter.h>
#include <levelfuse/io/scans/PtxScan.h>

namespace levelfuse::io {

/// Reads the columns * rows point lines that follow `header`, each taken into
/// the scanner's frame (a point "0 0 0" stays at the origin: no return).
/// `interrupter` is asked every 65536 points. Throws InputError naming the
/// file and line for a line of other than 4 or 7 fields or of another count
/// than the scan's first, a number that is not finite, a colour that is not a
/// whole number from 0 to 255, a file that ends before the last point, and a
/// scan without returns.
PtxScan readPtxPoints(TextLineReader& lines, const PtxHeader& header, const Interrupter& interrupter);

}  // namespace levelfuse::io
