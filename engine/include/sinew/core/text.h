// Text from files in any encoding. Sinew's strings (joint names, clip names, labels) are UTF-8:
// readers keep text that already is valid UTF-8 and read anything else as Latin-1 (ISO 8859-1,
// what European capture software writes: "Hüfte" with ü as one byte 0xFC), converting it. Every
// byte sequence is valid Latin-1, so the conversion never fails and never loses a character.
// Paths stay bytes (std::filesystem opens them as given); only what is shown or written as text
// goes through toUtf8.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace sinew {

// True when `text` is well-formed UTF-8 (no overlong forms, surrogates or code points past
// U+10FFFF; RFC 3629).
bool isValidUtf8(std::string_view text);

// `text` unchanged when it is valid UTF-8, else every byte read as Latin-1 and written as UTF-8.
std::string toUtf8(std::string_view text);

// The inverse of toUtf8's conversion: the Latin-1 bytes of UTF-8 text, or nothing when `text` is
// not valid UTF-8 or holds a code point past U+00FF. A path that is not UTF-8 is stored as
// toUtf8(path) (readable in JSON) and its bytes come back exactly through this.
std::optional<std::string> latin1FromUtf8(std::string_view text);

// `text` without a leading UTF-8 byte-order mark (EF BB BF), which some Windows tools write.
std::string_view withoutBom(std::string_view text);

// Reader input as UTF-8 text: without its byte-order mark, converted from Latin-1 when it is not
// UTF-8. A whole file is converted as one, so a file mixing both is read as Latin-1 throughout.
std::string textAsUtf8(std::string_view file_text);

// The first control character (bytes 0x00-0x1F and 0x7F) in `text`, or -1 when there is none:
// names with one cannot be written back to BVH (a NUL cuts a glTF name short) and are refused.
int firstControlCharacter(std::string_view text);

}  // namespace sinew
