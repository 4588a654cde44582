// levelfuse: the error every reader throws for bad input.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>

namespace levelfuse::io {

/// Bad input: names the file and says what is wrong with it, e.g.
/// "scans/bun000.ply: line 27: vertex 3 has 2 values, the header declares 3".
class InputError : public std::runtime_error {
 public:
  InputError(const std::string& file, const std::string& problem)
      : std::runtime_error(file + ": " + problem), mFile(file), mProblem(problem) {}
  const std::string& file() const { return mFile; }
  const std::string& problem() const { return mProblem; }

 private:
  std::string mFile, mProblem;
};

/// Bytes of a message that are not printable (control characters, DEL) as
/// \xNN: one line, safe for a terminal.
std::string escaped(std::string_view text);

/// How much of an input a message quotes at most.
inline constexpr std::size_t kExcerptBytes = 80;

/// `text` as a message quotes it: in single quotes, escaped, and cut after
/// kExcerptBytes bytes ("..." marks the cut). Every reader quotes input so.
std::string quote(std::string_view text);

/// A third party's message (a library's exception) as a message may hold it:
/// escaped and cut after `limit` bytes.
std::string excerpt(std::string_view text, std::size_t limit = 4 * kExcerptBytes);

}  // namespace levelfuse::io
