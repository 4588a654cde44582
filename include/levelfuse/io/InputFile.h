// levelfuse: what a reader checks before it opens an input, and which files a
// run has read (so that no output replaces one of them).
#pragma once

#include <string>
#include <vector>

namespace levelfuse::io {

/// Every reader calls this before it opens `path`: throws InputError unless
/// `path` is a regular file (or, with `folderToo`, a folder). A FIFO, a socket
/// or a device is refused: opening one blocks or never ends. The file is
/// recorded in inputsRead().
void requireInputFile(const std::string& path, bool folderToo = false);

/// Every file and folder requireInputFile() accepted in this process, in order,
/// each once.
std::vector<std::string> inputsRead();

/// Throws std::runtime_error naming the output if one of `outputs` is the same
/// file as one of `inputs`: the same device and inode, so a second name, a
/// symbolic link or a hard link does not hide it. Outputs that do not exist
/// yet are no input.
void refuseOverwritingInputs(const std::vector<std::string>& outputs, const std::vector<std::string>& inputs);

}  // namespace levelfuse::io
