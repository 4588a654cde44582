// levelfuse: quoting input in messages.

#include <levelfuse/io/InputError.h>

namespace levelfuse::io {

std::string escaped(std::string_view text) {
  static const char kHex[] = "0123456789abcdef";
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte >= 0x20 && byte != 0x7f) {
      out += c;
    } else {
      out += "\\x";
      out += kHex[byte >> 4];
      out += kHex[byte & 15];
    }
  }
  return out;
}

std::string excerpt(std::string_view text, std::size_t limit) {
  if (text.size() <= limit) return escaped(text);
  return escaped(text.substr(0, limit)) + "...";
}

std::string quote(std::string_view text) { return "'" + excerpt(text, kExcerptBytes) + "'"; }

}  // namespace levelfuse::io
