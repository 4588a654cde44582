// levelfuse CLI: lengths, areas, volumes and durations as a person reads them.
//
// The readers give world coordinates in metres (Stanford scans, depth frames,
// TUM sequences), so the text summaries print a length with the unit its size
// calls for, "0.50 mm", "0.093 mm", "1.2 cm", "3.4 m", and --json keeps SI
// metres.
#pragma once

#include <string>

namespace levelfuse::cli {

/// A length in metres, to two significant digits, in µm, mm, cm or m:
/// "0.50 mm", "1.2 cm". Zero is "0 m"; a value that is not finite prints as
/// itself with "m".
std::string length(double metres);
/// An area in square metres, to three significant digits, in mm², cm² or m².
std::string area(double squareMetres);
/// A volume in cubic metres, to three significant digits, in mm³, cm³ or m³.
std::string volume(double cubicMetres);
/// A duration in seconds, to a hundredth below 10 s and a tenth above: "0.62 s", "12.4 s".
std::string duration(double seconds);

}  // namespace levelfuse::cli
