// levelfuse: output files that appear whole or not at all.
#pragma once

#include <functional>
#include <string>

namespace levelfuse::io {

/// Calls write(temporaryPath) to produce the file beside `path`, then renames it
/// over `path`. If write throws or the rename fails, the temporary is removed,
/// an existing file at `path` is untouched, and std::runtime_error names `path`.
/// Something at `path` that is not a regular file (a folder, a device such as
/// /dev/null) is never replaced: that throws too.
void writeAtomically(const std::string& path, const std::function<void(const std::string& temporaryPath)>& write);

}  // namespace levelfuse::io
