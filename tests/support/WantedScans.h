// What a reader is told of the scans wanted (io::ScanLoadOptions::wanted), for
// the tests of readers that read a part of their scans.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

namespace levelfuse::test {

/// Wants every scan but the one numbered `skipped`, writing each number it is asked of into `asked`.
inline std::function<bool(std::size_t)> everyScanBut(std::size_t skipped, std::vector<std::size_t>& asked) {
  return [skipped, &asked](std::size_t scan) {
    asked.push_back(scan);
    return scan != skipped;
  };
}

}  // namespace levelfuse::test
