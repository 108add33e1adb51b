#pragma once
// Where each value of a JSON text starts, by JSON pointer ("/surfaces/0/equation"), so
// that errors found after parsing (a wrong type, an unknown material, a bad equation) can
// name the file, line and column. nlohmann-json does not keep positions, so this is a
// small second scanner over text nlohmann has already accepted.
#include <cstddef>
#include <map>
#include <string>
#include <string_view>

namespace algray::render {

struct TextLocation {
  int line = 1, column = 1;  // 1-based; column counts bytes
};

// Byte offset -> line and column.
TextLocation locateOffset(std::string_view text, size_t offset);

// JSON pointer of every value -> byte offset of its first character. Only valid JSON
// is expected (the scanner stops quietly at anything else).
std::map<std::string, size_t> locateJsonValues(std::string_view text);

}  // namespace algray::render
