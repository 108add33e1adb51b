#pragma once
// Reader for SURFER/jsurf surface files (Java properties format: `key=value` lines,
// `#`/`!` comments, backslash escapes and line continuations). It only reads; what the
// keys mean for a picture (camera, rotation_matrix, scale_factor, materials, lights) is
// the renderer's business (examples/render).
#include "algray/parser.h"

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace algray {

class JsurfFile {
 public:
  // Throws Error("NAME:LINE: message") on malformed input (a bad \uXXXX escape); NAME is
  // used in messages. Later duplicates of a key replace earlier ones, as in Java.
  static JsurfFile parse(std::string_view text, std::string name = "<jsurf>");
  // Reads a file; Error("PATH: cannot read") if it cannot be opened.
  static JsurfFile read(const std::filesystem::path& path);

  const std::string& name() const { return name_; }
  bool has(std::string_view key) const;
  std::optional<std::string> get(std::string_view key) const;
  int lineOf(std::string_view key) const;  // 1-based line of the key, 0 if absent
  // Whitespace-separated numbers of a key; throws Error with file:line if not numbers
  // or (when expected >= 0) not exactly `expected` of them.
  std::vector<double> getNumbers(std::string_view key, int expected = -1) const;
  double getNumber(std::string_view key, double fallback) const;

  // surface_parameter_<name> entries, ready for ParseOptions::parameters.
  std::map<std::string, double, std::less<>> parameters() const;
  // The surface_equation parsed with those parameters; a ParseError is rethrown as
  // Error("NAME:LINE:COLUMN: message").
  Polynomial polynomial(int maxDegree = kMaxDegree) const;

 private:
  struct Entry {
    std::string value;
    int line = 0;
    // Source (line, column) of each code point of the value, so that an error in the
    // equation points into the file even across escapes and line continuations.
    std::vector<std::pair<int, int>> positions;
  };
  // Source (line, column) of the value's 1-based column (> 0; positions not empty).
  static std::pair<int, int> position(const Entry& entry, int column);
  std::string where(const Entry& entry, int column = 0) const;
  std::string name_;
  std::map<std::string, Entry, std::less<>> entries_;
};

}  // namespace algray
