// levelfuse: a text file read line by line, each line split into fields
// (words between spaces or tabs), with the line's number for messages
// (private to the readers).
#pragma once

#include <levelfuse/scan/Colour.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace levelfuse::io {

class TextLineReader {
 public:
  /// Lines longer than this are refused: no text format levelfuse reads
  /// writes them, and a file without line breaks must not be held whole.
  static constexpr std::size_t kMaxLineBytes = 4096;

  /// Opens `path` (requireInputFile); InputError if it cannot be read.
  explicit TextLineReader(const std::string& path);

  /// Reads the next line (a trailing CR is dropped); false at the end of the
  /// file. InputError for a line longer than kMaxLineBytes or a read error.
  bool next();

  const std::string& path() const { return mPath; }
  /// The number of the line last read (1 for the first); 0 before any.
  std::int64_t lineNumber() const { return mLineNumber; }
  /// "line N: ", for messages.
  std::string at() const;
  /// Bytes of the file after the line last read (by its size when opened).
  std::uintmax_t bytesLeft() const { return mConsumed < mFileBytes ? mFileBytes - mConsumed : 0; }

  /// The line last read, without its line break.
  std::string_view line() const { return mLine; }
  std::size_t fieldCount() const { return mFields.size(); }
  std::string_view field(std::size_t i) const { return mFields[i]; }

  /// InputError naming the file and the line last read.
  [[noreturn]] void fail(const std::string& problem) const;
  /// Field `i` as a finite number; fails naming it otherwise.
  double number(std::size_t i) const;
  /// Field `i` as a whole number from `lowest` to `highest`, if it is one.
  std::optional<long long> wholeNumberIn(std::size_t i, long long lowest, long long highest) const;
  /// The same, failing with "'<field>' is not <what>" if it is not one.
  long long wholeNumber(std::size_t i, long long lowest, long long highest, const std::string& what) const;
  /// Fields `first` to `first + 2` as a colour: red, green and blue, whole
  /// numbers from 0 to 255; fails naming the field that is not one.
  Rgb8 colour(std::size_t first) const;

 private:
  /// Moves what is left of the buffer to its front and reads more after it;
  /// false if nothing more could be read.
  bool refill();
  void splitFields();

  std::string mPath;
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> mFile;
  std::uintmax_t mFileBytes = 0, mConsumed = 0;
  std::vector<char> mBuffer;
  std::size_t mBegin = 0, mEnd = 0;  ///< the unread bytes of the buffer
  bool mAtEnd = false;
  std::int64_t mLineNumber = 0;
  std::string_view mLine;
  std::vector<std::string_view> mFields;
};

}  // namespace levelfuse::io
