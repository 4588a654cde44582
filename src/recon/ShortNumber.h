// levelfuse: a number as messages print it, three significant digits.
#pragma once

#include <sstream>
#include <string>

namespace levelfuse::detail {

inline std::string shortNumber(double value) {
  std::ostringstream text;
  text.precision(3);
  text << value;
  return text.str();
}

}  // namespace levelfuse::detail
