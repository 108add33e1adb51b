#include "ray_csv.h"

#include "number_text.h"
#include "text_lines.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <istream>
#include <ostream>
#include <string>
#include <string_view>
#include <utility>

namespace algray::query {

namespace {

// The required columns, then the optional one (kRequired: the count of the first).
constexpr std::array<std::string_view, 9> kColumns = {"ox", "oy",    "oz",   "dx",       "dy",
                                                      "dz", "tnear", "tfar", "org_error"};
constexpr size_t kRequired = 8, kOrgError = 8;

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

// The fields of a line as RFC 4180 writes them: separated by commas, each either plain
// (spaces and tabs around it trimmed) or in double quotes, inside which a comma is text and
// "" is one quote (spreadsheets and R's write.csv quote headers and text columns: "ox" was
// "no column 'ox'", a quoted comment with a comma "expected 9 fields, found 10"). A quote
// left open is refused (a field across lines is not a ray's). Returns false with `error`.
bool split(std::string_view line, std::vector<std::string>& fields, std::string& error) {
  fields.clear();
  size_t i = 0;
  while (true) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    std::string field;
    if (i < line.size() && line[i] == '"') {
      const size_t open = i++;
      while (true) {
        if (i >= line.size()) {
          error = "field " + std::to_string(fields.size() + 1) + ": the quote at character " +
                  std::to_string(open + 1) + " is not closed on its line";
          return false;
        }
        if (line[i] == '"') {
          if (i + 1 < line.size() && line[i + 1] == '"') {
            field += '"';
            i += 2;
            continue;
          }
          ++i;
          break;
        }
        field += line[i++];
      }
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
      if (i < line.size() && line[i] != ',') {
        error = "field " + std::to_string(fields.size() + 1) +
                ": text after its closing quote at character " + std::to_string(i + 1);
        return false;
      }
    } else {
      const size_t comma = line.find(',', i);
      field = std::string(trim(
          line.substr(i, comma == std::string_view::npos ? std::string_view::npos : comma - i)));
      i = comma == std::string_view::npos ? line.size() : comma;
    }
    fields.push_back(std::move(field));
    if (i >= line.size()) return true;
    ++i;  // the comma
  }
}

// A field as a message shows it: control bytes as \xHH (a NUL byte cut the message short,
// a carriage return overwrote it on a terminal).
std::string shown(std::string_view field) {
  std::string s;
  for (const char c : field) {
    const auto b = static_cast<unsigned char>(c);
    if (b < 0x20 || b == 0x7f) {
      constexpr char kHex[] = "0123456789ABCDEF";
      s += {'\\', 'x', kHex[b >> 4], kHex[b & 15]};
    } else {
      s += c;
    }
  }
  return s;
}

[[noreturn]] void fail(const std::string& name, long long line, const std::string& message) {
  throw CsvError(name + ":" + std::to_string(line) + ": " + message);
}

}  // namespace

std::vector<RayD> readRays(std::istream& in, const std::string& name, bool* hasOrgError) {
  // Lines end in "\n", "\r\n" or a lone "\r" (classic Mac OS text, which getline alone read
  // as one line: "the header has no column 'tfar'").
  std::string_view text;
  algray::text::LineReader lines(in);
  long long lineNo = 0;
  // ---- Header: map each required column to its field index --------------------------
  std::array<int, kColumns.size()> where;
  where.fill(-1);
  size_t fieldCount = 0;
  std::vector<std::string> fields;
  std::string error;
  while (lines.next(text)) {
    lineNo = lines.number();
    // A UTF-8 byte order mark, as Excel writes it, is not part of the first column name
    // (nor after blank lines, where joining files puts it).
    if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);
    if (trim(text).empty()) continue;
    if (!split(text, fields, error)) fail(name, lineNo, "header, " + error);
    fieldCount = fields.size();
    for (size_t f = 0; f < fields.size(); ++f)
      for (size_t c = 0; c < kColumns.size(); ++c)
        if (fields[f] == kColumns[c]) {
          if (where[c] >= 0)
            fail(name, lineNo, "column '" + std::string(kColumns[c]) + "' appears twice");
          where[c] = static_cast<int>(f);
        }
    break;
  }
  // A read error is not the end of the file (/proc/self/mem read nothing and was "empty").
  if (in.bad()) fail(name, std::max(lineNo, 1LL), "read error");
  // Lines are 1-based: a file without a single line is reported at line 1.
  if (fieldCount == 0)
    fail(name, std::max(lineNo, 1LL),
         "empty file: expected the header ox,oy,oz,dx,dy,dz,tnear,tfar");
  for (size_t c = 0; c < kRequired; ++c)
    if (where[c] < 0)
      fail(name, lineNo,
           "the header has no column '" + std::string(kColumns[c]) +
               "' (need ox,oy,oz,dx,dy,dz,tnear,tfar in any order)");

  // ---- Rows ----------------------------------------------------------------------------
  std::vector<RayD> rays;
  while (lines.next(text)) {
    lineNo = lines.number();
    if (trim(text).empty()) continue;
    if (!split(text, fields, error)) fail(name, lineNo, error);
    if (fields.size() != fieldCount)
      fail(name, lineNo,
           "expected " + std::to_string(fieldCount) + " fields, found " +
               std::to_string(fields.size()));
    double v[kColumns.size()] = {};
    for (size_t c = 0; c < kColumns.size(); ++c) {
      if (where[c] < 0) continue;  // the optional column, absent
      const std::string& field = fields[where[c]];
      const std::string at =
          "column '" + std::string(kColumns[c]) + "' (field " + std::to_string(where[c] + 1) + ")";
      // As the tools read an option's number (number_text.h): a literal outside double's
      // range is named, a subnormal one is its value.
      const algray::cli::Number number = algray::cli::readNumber(field);
      v[c] = number.value;
      if (number.problem == algray::cli::NumberProblem::kNotANumber)
        fail(name, lineNo, at + ": not a number: '" + shown(field) + "'");
      if (number.problem == algray::cli::NumberProblem::kOverflows)
        fail(name, lineNo, at + ": '" + shown(field) + "' overflows double");
      if (number.problem == algray::cli::NumberProblem::kUnderflows)
        fail(name, lineNo, at + ": '" + shown(field) + "' underflows to 0 in double");
      if (std::isnan(v[c])) fail(name, lineNo, at + ": NaN is not a valid value");
      const bool isTfar = kColumns[c] == "tfar";
      if (std::isinf(v[c]) && !(isTfar && v[c] > 0))
        fail(name, lineNo, at + ": must be finite: '" + shown(field) + "'");
    }
    RayD ray;
    ray.org = {v[0], v[1], v[2]};
    ray.dir = {v[3], v[4], v[5]};
    ray.tnear = v[6];
    ray.tfar = v[7];
    ray.orgError = v[kOrgError];
    auto columns = [&](size_t first, size_t last) {  // "column 'dx' (field 4)", ...
      std::string s;
      for (size_t c = first; c <= last; ++c)
        s += std::string(c > first ? ", " : "") + "column '" + std::string(kColumns[c]) +
             "' (field " + std::to_string(where[c] + 1) + ")";
      return s;
    };
    // A zero direction has no ray to trace; a negative or reversed interval none to search
    // (tfar may be inf, tnear must be finite, both checked above).
    if (ray.dir == glm::dvec3(0.0)) fail(name, lineNo, columns(3, 5) + ": the direction is zero");
    if (ray.tnear < 0.0) fail(name, lineNo, columns(6, 6) + ": must be >= 0");
    if (ray.tfar < ray.tnear) fail(name, lineNo, columns(7, 7) + ": must be >= tnear");
    if (ray.orgError < 0.0) fail(name, lineNo, columns(kOrgError, kOrgError) + ": must be >= 0");
    rays.push_back(ray);
  }
  if (in.bad()) fail(name, lineNo + 1, "read error");
  if (hasOrgError) *hasOrgError = where[kOrgError] >= 0;
  return rays;
}

void writeHits(std::ostream& out, const std::vector<QueryHit>& hits) {
  out << "hit,t,nx,ny,nz\n";
  char buf[160];
  for (const QueryHit& h : hits) {
    if (!h.hit) {
      out << "0,0,0,0,0\n";
      continue;
    }
    std::snprintf(buf, sizeof buf, "1,%.17g,%.17g,%.17g,%.17g\n", h.t, h.normal.x, h.normal.y,
                  h.normal.z);
    out << buf;
  }
}

}  // namespace algray::query
