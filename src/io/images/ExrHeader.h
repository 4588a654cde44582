// levelfuse: what an EXR file's header declares, read before OpenEXR is given
// the file (private to the depth-image reader).
#pragma once

#include <cstdint>
#include <string>

namespace levelfuse::io::detail {

/// The parts of an EXR header (of its first part) that size its pixels.
struct ExrLayout {
  double width = 0.0, height = 0.0;  ///< of the data window, in pixels
  double bytesPerPixel = 0.0;        ///< over all channels, as stored uncompressed
  int compression = -1;              ///< OpenEXR's Compression number; -1 if the header names none
};

/// Reads the header of the EXR file at `path` with bounded reads of its own:
/// every attribute's declared size is held against the file's. Returns an
/// empty string and fills `layout`, or says what is wrong.
std::string readExrLayout(const std::string& path, std::uintmax_t fileBytes, ExrLayout& layout);

/// At most how many times a file's size its pixels can take, uncompressed,
/// under OpenEXR's compression `compression` (generous where a scheme's bound
/// is not known exactly: the check must never refuse a file OpenEXR reads).
double exrMaxCompressionRatio(int compression);

}  // namespace levelfuse::io::detail
