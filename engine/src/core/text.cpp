#include "sinew/core/text.h"

namespace sinew {

bool isValidUtf8(std::string_view text) {
  size_t n = 0;
  while (n < text.size()) {
    const auto byte = static_cast<unsigned char>(text[n]);
    if (byte < 0x80) {
      ++n;
      continue;
    }
    int extra = 0;
    unsigned lowest = 0;  // smallest code point for this length (rejects overlong forms)
    unsigned code = 0;
    if ((byte & 0xE0) == 0xC0) {
      extra = 1, lowest = 0x80, code = byte & 0x1Fu;
    } else if ((byte & 0xF0) == 0xE0) {
      extra = 2, lowest = 0x800, code = byte & 0x0Fu;
    } else if ((byte & 0xF8) == 0xF0) {
      extra = 3, lowest = 0x10000, code = byte & 0x07u;
    } else {
      return false;
    }
    if (text.size() - n <= static_cast<size_t>(extra)) return false;
    for (int k = 1; k <= extra; ++k) {
      const auto next = static_cast<unsigned char>(text[n + k]);
      if ((next & 0xC0) != 0x80) return false;
      code = (code << 6) | (next & 0x3Fu);
    }
    if (code < lowest || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) return false;
    n += static_cast<size_t>(extra) + 1;
  }
  return true;
}

std::string toUtf8(std::string_view text) {
  if (isValidUtf8(text)) return std::string(text);
  std::string out;
  out.reserve(text.size() + text.size() / 4);
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x80) {
      out += c;
    } else {
      out += static_cast<char>(0xC0 | (byte >> 6));
      out += static_cast<char>(0x80 | (byte & 0x3F));
    }
  }
  return out;
}

std::optional<std::string> latin1FromUtf8(std::string_view text) {
  if (!isValidUtf8(text)) return std::nullopt;
  std::string out;
  out.reserve(text.size());
  for (size_t i = 0; i < text.size(); ++i) {
    const auto byte = static_cast<unsigned char>(text[i]);
    if (byte < 0x80) {
      out += text[i];
    } else if ((byte == 0xC2 || byte == 0xC3) && i + 1 < text.size()) {
      out += static_cast<char>(((byte & 0x03) << 6) | (static_cast<unsigned char>(text[++i]) & 0x3F));
    } else {
      return std::nullopt;  // a code point past U+00FF has no Latin-1 byte
    }
  }
  return out;
}

std::string_view withoutBom(std::string_view text) {
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  return text;
}

std::string textAsUtf8(std::string_view file_text) {
  return toUtf8(withoutBom(file_text));
}

int firstControlCharacter(std::string_view text) {
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte == 0x7F) return byte;
  }
  return -1;
}

}  // namespace sinew
