#pragma once
// Where each value of a JSON text starts, by JSON pointer ("/surfaces/0/equation"), so
// that errors found after parsing (a wrong type, an unknown material, a bad equation) can
// name the file, line and column. nlohmann-json does not keep positions, so this is a
// small second scanner over text nlohmann has already accepted.
#include <cstddef>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace algray::render {

struct TextLocation {
  int line = 1, column = 1;  // 1-based; column counts characters (UTF-8 code points), as
                             // the equation parser's columns and editors do
};

// Byte offset -> line and column.
TextLocation locateOffset(std::string_view text, size_t offset);

// A key that occurs twice in one object (nlohmann keeps the last one silently).
struct DuplicateKey {
  std::string pointer;  // JSON pointer of the (second) value
  std::string key;      // decoded
  size_t first = 0;     // byte offsets of the two key strings
  size_t second = 0;
};

// JSON pointer of every value -> byte offset of its first character. Only valid JSON
// is expected (the scanner stops quietly at anything else). Keys are decoded (every
// escape, \uXXXX included) and escaped with jsonPointerToken, as the loader builds its
// pointers. With `duplicates`, keys repeated within an object are reported there.
std::map<std::string, size_t> locateJsonValues(std::string_view text,
                                               std::vector<DuplicateKey>* duplicates = nullptr);

// Byte offset in `text` of the character at 1-based `column` (counted in code points, as
// ParseError counts them) of the decoded value of the JSON string whose opening quote is at
// byte `quote`: an error inside a decoded string (an equation's column) then points at the
// same character in the file, escapes and multi-byte characters before it included. A
// column past the string's end gives its closing quote.
size_t stringCharacterOffset(std::string_view text, size_t quote, int column);

// One reference token of a JSON pointer (RFC 6901: '~' -> "~0", '/' -> "~1"). The loader
// and the scanner must build pointers the same way, or a key with '/' or '~' has no
// location.
std::string jsonPointerToken(std::string_view key);

// Byte offset of the '[' or '{' that opens nesting level maxDepth + 1 (outside strings),
// or npos. Checked before parsing: nlohmann's parser and value destructor and the scanner
// above recurse once per level, so a file of 100000 '[' overflowed the stack (SIGSEGV).
size_t findExcessiveNesting(std::string_view text, int maxDepth);

// Byte offset of a number token spelled exactly `literal` outside strings, or npos: for
// nlohmann's number overflow error, which quotes the literal but gives no position.
size_t locateNumberLiteral(std::string_view text, std::string_view literal);

}  // namespace algray::render
