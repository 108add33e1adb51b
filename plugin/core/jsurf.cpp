// SURFER/jsurf files are java.util.Properties text (the format of Properties.load(Reader)):
//  * a logical line may continue over several natural lines: a line ending in an odd
//    number of backslashes continues, and the next line's leading whitespace is skipped;
//  * blank lines and lines whose first non-blank character is '#' or '!' are comments;
//  * the key ends at the first unescaped '=', ':' or whitespace; whitespace, then at most
//    one '=' or ':', then whitespace separate it from the value;
//  * escapes: \t \n \r \f, \uXXXX, and \c = c for any other c (so "\:" and "\=" and
//    "\\" are literal).
#include "algray/jsurf.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <system_error>

namespace algray {

namespace {

bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\f'; }
bool isContinuation(char c) { return (static_cast<unsigned char>(c) & 0xC0) == 0x80; }

// One character of a logical line with where it came from.
struct SourceChar {
  char c;
  int line, column;
};

void appendUtf8(std::string& out, unsigned code) {
  if (code < 0x80) {
    out += static_cast<char>(code);
  } else if (code < 0x800) {
    out += static_cast<char>(0xC0 | (code >> 6));
    out += static_cast<char>(0x80 | (code & 0x3F));
  } else if (code < 0x10000) {
    out += static_cast<char>(0xE0 | (code >> 12));
    out += static_cast<char>(0x80 | ((code >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (code & 0x3F));
  } else {
    out += static_cast<char>(0xF0 | (code >> 18));
    out += static_cast<char>(0x80 | ((code >> 12) & 0x3F));
    out += static_cast<char>(0x80 | ((code >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (code & 0x3F));
  }
}

bool isHighSurrogate(unsigned code) { return code >= 0xD800 && code <= 0xDBFF; }
bool isLowSurrogate(unsigned code) { return code >= 0xDC00 && code <= 0xDFFF; }

// Splits the text into logical lines (continuations joined, comments dropped).
std::vector<std::vector<SourceChar>> logicalLines(std::string_view text) {
  std::vector<std::vector<SourceChar>> lines;
  std::vector<SourceChar> current;
  bool continuing = false;
  int lineNo = 0;
  size_t i = 0;
  while (i <= text.size()) {
    // One natural line [i, end).
    size_t end = i;
    while (end < text.size() && text[end] != '\n' && text[end] != '\r') ++end;
    ++lineNo;
    size_t s = i;
    while (s < end && isBlank(text[s])) ++s;
    const bool comment = !continuing && s < end && (text[s] == '#' || text[s] == '!');
    if (!comment && (s < end || continuing)) {
      int column = 1;
      for (size_t k = i; k < s; ++k) column += !isContinuation(text[k]);
      for (size_t k = s; k < end; ++k) {
        current.push_back({text[k], lineNo, column});
        if (!isContinuation(text[k])) ++column;
      }
      // An odd number of trailing backslashes continues the logical line.
      size_t backslashes = 0;
      for (size_t k = end; k > s && text[k - 1] == '\\'; --k) ++backslashes;
      continuing = backslashes % 2 == 1;
      if (continuing) current.pop_back();
      if (!continuing || end >= text.size()) {
        if (!current.empty()) lines.push_back(std::move(current));
        current.clear();
      }
    }
    if (end >= text.size()) break;
    i = end + 1;
    if (text[end] == '\r' && i < text.size() && text[i] == '\n') ++i;
  }
  return lines;
}

}  // namespace

JsurfFile JsurfFile::parse(std::string_view text, std::string name) {
  // A UTF-8 byte order mark (an editor's, never SURFER's) is not part of the first key (it
  // made the file "no surface_equation").
  if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);
  JsurfFile file;
  file.name_ = std::move(name);
  for (const auto& line : logicalLines(text)) {
    // Unescapes [from, to) of the line; stops (for the key) at an unescaped separator.
    size_t k = 0;
    auto readPart = [&](bool isKey, Entry& out) {
      while (k < line.size()) {
        const SourceChar& sc = line[k];
        if (isKey && (sc.c == '=' || sc.c == ':' || isBlank(sc.c))) return;
        ++k;
        if (sc.c != '\\') {
          out.value += sc.c;
          if (!isContinuation(sc.c)) out.positions.emplace_back(sc.line, sc.column);
          continue;
        }
        if (k >= line.size()) return;  // a lone trailing backslash at the end of the file
        const char e = line[k++].c;
        if (e == 'u') {
          // Four hex digits at line[at..at+4): one UTF-16 code unit.
          auto hexUnit = [&](size_t at) {
            const Error malformed(file.name_ + ":" + std::to_string(sc.line) +
                                  ": malformed \\uXXXX escape");
            unsigned code = 0;
            if (at + 4 > line.size()) throw malformed;
            std::string hex;
            for (int d = 0; d < 4; ++d) hex += line[at + d].c;
            const auto [ptr, ec] = std::from_chars(hex.data(), hex.data() + 4, code, 16);
            if (ec != std::errc() || ptr != hex.data() + 4) throw malformed;
            return code;
          };
          unsigned code = hexUnit(k);
          k += 4;
          // Java strings are UTF-16: a character beyond U+FFFF is escaped as a surrogate
          // pair, which is one code point (encoding each half on its own would give
          // invalid UTF-8). A lone surrogate has no UTF-8 form: U+FFFD.
          if (isHighSurrogate(code) && k + 6 <= line.size() && line[k].c == '\\' &&
              line[k + 1].c == 'u') {
            const unsigned low = hexUnit(k + 2);
            if (isLowSurrogate(low)) {
              code = 0x10000 + ((code - 0xD800) << 10) + (low - 0xDC00);
              k += 6;
            }
          }
          if (isHighSurrogate(code) || isLowSurrogate(code)) code = 0xFFFD;
          appendUtf8(out.value, code);
        } else {
          out.value += e == 't' ? '\t' : e == 'n' ? '\n' : e == 'r' ? '\r' : e == 'f' ? '\f' : e;
        }
        out.positions.emplace_back(sc.line, sc.column);
      }
    };
    Entry key;
    readPart(true, key);
    while (k < line.size() && isBlank(line[k].c)) ++k;
    if (k < line.size() && (line[k].c == '=' || line[k].c == ':')) ++k;
    while (k < line.size() && isBlank(line[k].c)) ++k;
    Entry value;
    value.line = line.front().line;
    readPart(false, value);
    file.entries_[key.value] = std::move(value);
  }
  return file;
}

JsurfFile JsurfFile::read(const std::filesystem::path& path) {
  // An ifstream opens a directory and reads nothing: it was an empty file.
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw Error(path.string() + ": is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path.string() + ": cannot read");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return parse(buffer.str(), path.string());
}

bool JsurfFile::has(std::string_view key) const { return entries_.find(key) != entries_.end(); }

std::optional<std::string> JsurfFile::get(std::string_view key) const {
  const auto it = entries_.find(key);
  if (it == entries_.end()) return std::nullopt;
  return it->second.value;
}

int JsurfFile::lineOf(std::string_view key) const {
  const auto it = entries_.find(key);
  return it == entries_.end() ? 0 : it->second.line;
}

std::pair<int, int> JsurfFile::position(const Entry& entry, int column) {
  // Column c of the value is its code point c - 1, or one past the last one.
  const size_t i = static_cast<size_t>(column - 1);
  return i < entry.positions.size()
             ? entry.positions[i]
             : std::pair{entry.positions.back().first, entry.positions.back().second + 1};
}

std::string JsurfFile::where(const Entry& entry, int column) const {
  if (column <= 0 || entry.positions.empty()) return name_ + ":" + std::to_string(entry.line);
  const auto [line, col] = position(entry, column);
  return name_ + ":" + std::to_string(line) + ":" + std::to_string(col);
}

std::vector<double> JsurfFile::getNumbers(std::string_view key, int expected) const {
  const auto it = entries_.find(key);
  if (it == entries_.end()) throw Error(name_ + ": missing key '" + std::string(key) + "'");
  const std::string& v = it->second.value;
  std::vector<double> numbers;
  size_t i = 0;
  while (i < v.size()) {
    while (i < v.size() && (isBlank(v[i]) || v[i] == '\n' || v[i] == '\r')) ++i;
    if (i >= v.size()) break;
    size_t j = i;
    while (j < v.size() && !(isBlank(v[j]) || v[j] == '\n' || v[j] == '\r')) ++j;
    double d = 0.0;
    // Java writes "1.0E-4"; from_chars reads it, and a leading '+' is skipped by hand
    // (only one sign: "+-2" is not a number for Java either).
    const size_t from = v[i] == '+' ? i + 1 : i;
    const bool secondSign = from > i && from < j && (v[from] == '-' || v[from] == '+');
    auto [ptr, ec] = std::from_chars(v.data() + from, v.data() + j, d);
    if (ec == std::errc::result_out_of_range && ptr == v.data() + j) {
      // Below the subnormals Java's Double.parseDouble (and the equation's literals) round
      // to +-0; only an overflow is an error. from_chars says neither which nor the sign:
      // a long double (wider exponent range) tells, and beyond even its range a negative
      // decimal exponent does.
      long double wide = 0.0L;
      const auto r = std::from_chars(v.data() + from, v.data() + j, wide);
      const std::string_view token(v.data() + from, j - from);
      const size_t exponent = token.find_first_of("eE");
      const bool negativeExponent = exponent != std::string_view::npos &&
                                    exponent + 1 < token.size() && token[exponent + 1] == '-';
      const bool tiny = r.ec == std::errc() ? std::abs(wide) < 1.0L : negativeExponent;
      if (tiny) {
        d = token.front() == '-' ? -0.0 : 0.0;
        ec = std::errc();
      }
    }
    if (secondSign || ec != std::errc() || ptr != v.data() + j || !std::isfinite(d))
      throw Error(where(it->second) + ": " + std::string(key) + ": '" + v.substr(i, j - i) +
                  "' is not a finite number");
    numbers.push_back(d);
    i = j;
  }
  if (expected >= 0 && static_cast<int>(numbers.size()) != expected)
    throw Error(where(it->second) + ": " + std::string(key) + ": expected " +
                std::to_string(expected) + " numbers, found " + std::to_string(numbers.size()));
  return numbers;
}

double JsurfFile::getNumber(std::string_view key, double fallback) const {
  if (!has(key)) return fallback;
  return getNumbers(key, 1)[0];
}

std::map<std::string, double, std::less<>> JsurfFile::parameters() const {
  static constexpr std::string_view kPrefix = "surface_parameter_";
  std::map<std::string, double, std::less<>> result;
  for (const auto& [key, entry] : entries_) {
    if (key.compare(0, kPrefix.size(), kPrefix) != 0) continue;
    // (Without a name it was skipped, while "surface_parameter_1a" was refused: the audit of
    // session 51.)
    if (key.size() == kPrefix.size())
      throw Error(where(entry) + ": " + key + ": a parameter needs a name after the '_'");
    result[key.substr(kPrefix.size())] = getNumbers(key, 1)[0];
  }
  return result;
}

Polynomial JsurfFile::polynomial(int maxDegree) const {
  const auto it = entries_.find("surface_equation");
  if (it == entries_.end()) throw Error(name_ + ": no surface_equation");
  ParseOptions options;
  options.parameters = parameters();
  options.maxDegree = maxDegree;
  try {
    return parsePolynomial(it->second.value, options);
  } catch (const ParameterError& e) {
    // At the line of the parameter's own key, not in the equation.
    const std::string key = "surface_parameter_" + e.name();
    const auto p = entries_.find(key);
    throw Error((p != entries_.end() ? where(p->second) : name_) + ": " + key + ": " + e.message());
  } catch (const ParseError& e) {
    // A second place the message names ("... close '(' at column 9") in the file's terms
    // too: the equation's column beside the prefix's file column read as the same system.
    std::string message = e.message();
    if (e.relatedColumn() > 0 && !it->second.positions.empty()) {
      const auto [line, column] = position(it->second, e.relatedColumn());
      message =
          e.messageWith("line " + std::to_string(line) + ", column " + std::to_string(column));
    }
    throw Error(where(it->second, e.column()) + ": " + message);
  }
}

}  // namespace algray
