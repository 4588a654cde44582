// levelfuse: text files line by line.

#include "TextLineReader.h"

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/InputFile.h>

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>

namespace levelfuse::io {

namespace {

/// Bytes read from the file at a time.
constexpr std::size_t kBufferBytes = 64 << 10;
static_assert(kBufferBytes > 2 * TextLineReader::kMaxLineBytes, "a whole line and more fit the buffer");

bool isBlank(char c) { return c == ' ' || c == '\t'; }

}  // namespace

TextLineReader::TextLineReader(const std::string& path) : mPath(path), mFile(nullptr, &std::fclose) {
  requireInputFile(path);
  mFile.reset(std::fopen(path.c_str(), "rb"));
  if (!mFile) throw InputError(path, "cannot be opened for reading");
  std::error_code ec;  // the non-throwing overload: the size only bounds what the file can hold
  const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
  mFileBytes = ec ? 0 : bytes;
  mBuffer.resize(kBufferBytes);
}

std::string TextLineReader::at() const { return "line " + std::to_string(mLineNumber) + ": "; }

void TextLineReader::fail(const std::string& problem) const { throw InputError(mPath, at() + problem); }

bool TextLineReader::refill() {
  if (mAtEnd) return false;
  std::memmove(mBuffer.data(), mBuffer.data() + mBegin, mEnd - mBegin);
  mEnd -= mBegin;
  mBegin = 0;
  const std::size_t read = std::fread(mBuffer.data() + mEnd, 1, mBuffer.size() - mEnd, mFile.get());
  if (read == 0) {
    if (std::ferror(mFile.get())) throw InputError(mPath, "cannot be read (an input/output error)");
    mAtEnd = true;
    return false;
  }
  mEnd += read;
  return true;
}

bool TextLineReader::next() {
  mFields.clear();
  for (;;) {
    const char* begin = mBuffer.data() + mBegin;
    const auto* newline = static_cast<const char*>(std::memchr(begin, '\n', mEnd - mBegin));
    const std::size_t pending = mEnd - mBegin;
    if (newline || pending > kMaxLineBytes || !refill()) {
      if (!newline && pending == 0) return false;
      ++mLineNumber;
      const std::size_t length = newline ? static_cast<std::size_t>(newline - begin) : pending;
      if (length > kMaxLineBytes)
        fail("a line longer than " + std::to_string(kMaxLineBytes) + " bytes: not a text file of this kind");
      mLine = std::string_view(begin, length);
      if (!mLine.empty() && mLine.back() == '\r') mLine.remove_suffix(1);
      const std::size_t taken = newline ? length + 1 : length;
      mBegin += taken;
      mConsumed += taken;
      splitFields();
      return true;
    }
  }
}

void TextLineReader::splitFields() {
  std::size_t i = 0;
  while (i < mLine.size()) {
    while (i < mLine.size() && isBlank(mLine[i])) ++i;
    const std::size_t start = i;
    while (i < mLine.size() && !isBlank(mLine[i])) ++i;
    if (i > start) mFields.push_back(mLine.substr(start, i - start));
  }
}

double TextLineReader::number(std::size_t i) const {
  const std::string_view text = mFields[i];
  // from_chars takes no leading '+', which strtod (and so a writer's printf) may give.
  const std::size_t skip = text.size() > 1 && text[0] == '+' && text[1] != '-' ? 1 : 0;
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data() + skip, text.data() + text.size(), value);
  if (end != text.data() + text.size() || (error != std::errc() && error != std::errc::result_out_of_range))
    fail(quote(text) + " is not a number");
  // Out of range: an overflow (infinite, refused) or an underflow (near 0, as strtod gives it).
  if (error == std::errc::result_out_of_range) value = std::strtod(std::string(text).c_str(), nullptr);
  if (!std::isfinite(value)) fail(quote(text) + " is not a finite number");
  return value;
}

std::optional<long long> TextLineReader::wholeNumberIn(std::size_t i, long long lowest, long long highest) const {
  const std::string_view text = mFields[i];
  long long value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || value < lowest || value > highest)
    return std::nullopt;
  return value;
}

long long TextLineReader::wholeNumber(std::size_t i, long long lowest, long long highest,
                                      const std::string& what) const {
  const std::optional<long long> value = wholeNumberIn(i, lowest, highest);
  if (!value) fail(quote(mFields[i]) + " is not " + what);
  return *value;
}

Rgb8 TextLineReader::colour(std::size_t first) const {
  Rgb8 rgb{};
  for (std::size_t c = 0; c < 3; ++c)
    rgb[c] = static_cast<std::uint8_t>(wholeNumber(first + c, 0, 255, "a colour (a whole number from 0 to 255)"));
  return rgb;
}

}  // namespace levelfuse::io
