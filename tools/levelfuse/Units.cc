// levelfuse CLI: lengths, areas, volumes and durations as a person reads them.

#include "Units.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstddef>
#include <sstream>

namespace levelfuse::cli {

namespace {

struct Unit {
  const char* name;
  double metres;  ///< the unit's length in metres
  double from;    ///< the smallest magnitude (in metres^power) printed in it
};

/// `value` rounded to `digits` significant digits.
double roundToDigits(double value, int digits) {
  if (value == 0.0) return 0.0;
  const double scale = std::pow(10.0, digits - 1 - static_cast<int>(std::floor(std::log10(std::fabs(value)))));
  return std::round(value * scale) / scale;
}

/// `value` of dimension `power` (1 length, 2 area, 3 volume) in metres^power,
/// to `digits` significant digits, in the first of `units` whose range it
/// falls in (the last if none), with its trailing zeros: "0.50 mm".
template <std::size_t N>
std::string withUnit(double value, int power, int digits, const Unit (&units)[N], const char* suffix) {
  if (!std::isfinite(value)) {
    std::ostringstream text;
    text << value << " m" << suffix;
    return text.str();
  }
  const double rounded = roundToDigits(value, digits);
  if (rounded == 0.0) return std::string("0 m") + suffix;
  const Unit* unit = &units[N - 1];
  for (const Unit& u : units)
    if (std::fabs(rounded) >= u.from) {
      unit = &u;
      break;
    }
  const double scaled = roundToDigits(rounded / std::pow(unit->metres, power), digits);
  const int decimals = std::max(0, digits - 1 - static_cast<int>(std::floor(std::log10(std::fabs(scaled)))));
  std::ostringstream text;
  text.setf(std::ios::fixed);
  text.precision(decimals);
  text << scaled << " " << unit->name << suffix;
  return text.str();
}

}  // namespace

std::string length(double metres) {
  // From a hundredth of a millimetre in mm, so that a fit reads 0.093 mm.
  static const Unit units[] = {{"m", 1.0, 1.0}, {"cm", 1e-2, 1e-2}, {"mm", 1e-3, 1e-5}, {"µm", 1e-6, 0.0}};
  return withUnit(metres, 1, 2, units, "");
}

std::string area(double squareMetres) {
  static const Unit units[] = {{"m", 1.0, 1.0}, {"cm", 1e-2, 1e-4}, {"mm", 1e-3, 0.0}};
  return withUnit(squareMetres, 2, 3, units, "²");
}

std::string volume(double cubicMetres) {
  static const Unit units[] = {{"m", 1.0, 1.0}, {"cm", 1e-2, 1e-6}, {"mm", 1e-3, 0.0}};
  return withUnit(cubicMetres, 3, 3, units, "³");
}

std::string duration(double seconds) {
  char text[32];
  std::snprintf(text, sizeof text, seconds < 10.0 ? "%.2f s" : "%.1f s", seconds);
  return text;
}

}  // namespace levelfuse::cli
