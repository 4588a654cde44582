// libFuzzer targets: the fuzzer's bytes as files, since every reader takes a path.
#pragma once

#include <levelfuse/io/InputError.h>

#include <cstddef>
#include <cstdint>
#include <string>

namespace levelfuse::fuzz {

/// A folder of this process's own under the temporary folder ($TMPDIR),
/// created on first use and removed when the process exits.
const std::string& scratchFolder();

/// Writes `size` bytes to `name` in the scratch folder; returns its path.
std::string writeScratchFile(const std::string& name, const std::uint8_t* data, std::size_t size);
std::string writeScratchFile(const std::string& name, const std::string& text);

/// Runs a reader on fuzzed input. Bad input must end in InputError; any other
/// exception escapes and aborts the fuzzer, which records the input as a crash.
template <typename Read>
void expectOnlyInputErrors(Read&& read) {
  try {
    read();
  } catch (const io::InputError&) {
  }
}

}  // namespace levelfuse::fuzz
