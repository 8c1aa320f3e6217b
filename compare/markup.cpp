#include "compare/markup.h"

#include <cstdint>

namespace nightcap {
namespace {

// The length of the valid UTF-8 sequence starting at text[i], or 0 when there is none (overlong
// forms, surrogates and code points past U+10FFFF are not valid).
size_t utf8_sequence(std::string_view text, size_t i) {
  const auto byte = [&](size_t k) { return uint8_t(text[k]); };
  const uint8_t lead = byte(i);
  size_t length;
  uint32_t code;
  if (lead >= 0xc2 && lead <= 0xdf) {
    length = 2;
    code = lead & 0x1f;
  } else if (lead >= 0xe0 && lead <= 0xef) {
    length = 3;
    code = lead & 0x0f;
  } else if (lead >= 0xf0 && lead <= 0xf4) {
    length = 4;
    code = lead & 0x07;
  } else {
    return 0;
  }
  if (i + length > text.size()) return 0;
  for (size_t k = 1; k < length; ++k) {
    if ((byte(i + k) & 0xc0) != 0x80) return 0;
    code = code << 6 | (byte(i + k) & 0x3f);
  }
  const bool overlong = (length == 3 && code < 0x800) || (length == 4 && code < 0x10000);
  if (overlong || (code >= 0xd800 && code <= 0xdfff) || code > 0x10ffff) return 0;
  return length;
}

}  // namespace

std::string escape_markup(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (size_t i = 0; i < text.size();) {
    const char c = text[i];
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        if (uint8_t(c) >= 0x80) {
          const size_t length = utf8_sequence(text, i);
          if (length) {
            out.append(text.substr(i, length));
            i += length;
          } else {
            out += "\xef\xbf\xbd";
            ++i;
          }
          continue;
        }
        // Control characters other than tab and line breaks are not allowed in HTML text.
        if (uint8_t(c) < 0x20 && c != '\t' && c != '\n' && c != '\r')
          out += "\xef\xbf\xbd";
        else
          out += c;
    }
    ++i;
  }
  return out;
}

}  // namespace nightcap
