#include "FlagHints.h"

#include <string>
#include <utility>

namespace levelfuse::cli {
namespace {

/// The library's words for a setting it advises on, and the same with the flag.
const std::pair<const char*, const char*> kHints[] = {
    {"choose a voxel size of", "choose a voxel size (--voxel-size) of"},
    {"choose a window width epsilon of", "choose a window width (--epsilon) of"},
    {"a narrower window width epsilon", "a narrower window (--epsilon)"},
    {"and the window width epsilon", "and the window width (--epsilon)"},
    {"use more grids (levels)", "use more grids (--levels)"},
};

}  // namespace

std::string withFlagHints(std::string message) {
  for (const auto& [words, hinted] : kHints) {
    const std::string from = words, to = hinted;
    for (std::size_t at = message.find(from); at != std::string::npos; at = message.find(from, at + to.size()))
      message.replace(at, from.size(), to);
  }
  return message;
}

}  // namespace levelfuse::cli
