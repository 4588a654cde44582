// levelfuse CLI: the library's messages name settings as its API does ("a
// voxel size", "the window width epsilon"); the converter's user sets them
// with flags, which it names beside them.
#pragma once

#include <string>

namespace levelfuse::cli {

/// `message` with the flag that sets each setting it advises on named beside
/// it ("choose a voxel size (--voxel-size) of at least ...").
std::string withFlagHints(std::string message);

}  // namespace levelfuse::cli
