// The CSV reader of algray-query (examples/query/ray_csv.h) directly: columns in any
// order, line endings, quoting, byte-order marks, and rejected fields with their location;
// and its writer of hits.
#include "ray_csv.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

namespace {

TEST(RayCsv, ReaderParsesAndRejects) {
  std::istringstream ok("tnear , tfar,ox,oy,oz,dx,dy,dz\r\n0,inf,1,2,3,4,5,6\r\n\n");
  const auto rays = algray::query::readRays(ok, "ok.csv");
  ASSERT_EQ(rays.size(), 1u);
  EXPECT_EQ(rays[0].org, glm::dvec3(1, 2, 3));
  EXPECT_EQ(rays[0].dir, glm::dvec3(4, 5, 6));
  EXPECT_TRUE(std::isinf(rays[0].tfar));
  std::istringstream dup("ox,ox,oy,oz,dx,dy,dz,tnear,tfar\n");
  EXPECT_THROW(algray::query::readRays(dup, "dup.csv"), algray::query::CsvError);
  std::istringstream neg("ox,oy,oz,dx,dy,dz,tnear,tfar\n0,0,0,1,0,0,-1,1\n");
  EXPECT_THROW(algray::query::readRays(neg, "neg.csv"), algray::query::CsvError);
}

bool startsWith(const std::string& s, const std::string& prefix) { return s.starts_with(prefix); }

std::string csvError(const std::string& text) {
  std::istringstream in(text);
  try {
    algray::query::readRays(in, "t.csv");
  } catch (const algray::query::CsvError& e) {
    return e.what();
  }
  return "accepted";
}

TEST(RayCsv, RejectsDegenerateRaysAndOutOfRangeLiterals) {
  const std::string header = "ox,oy,oz,dx,dy,dz,tnear,tfar\n";
  EXPECT_EQ(csvError(header + "0,0,-5,0,0,0,0,inf\n"),
            "t.csv:2: column 'dx' (field 4), column 'dy' (field 5), column 'dz' (field 6): the "
            "direction is zero");
  EXPECT_PRED2(startsWith, csvError(header + "0,0,-5,0,-0,0,0,inf\n"), "t.csv:2:");
  EXPECT_EQ(csvError(header + "0,0,-5,0,0,1e-400,0,inf\n"),
            "t.csv:2: column 'dz' (field 6): '1e-400' underflows to 0 in double");
  EXPECT_PRED2(startsWith, csvError(header + "0,0,-5,0,0,1,-1e-400,inf\n"),
               "t.csv:2: column 'tnear' (field 7): '-1e-400' un");
  EXPECT_EQ(csvError(header + "1e999,0,-5,0,0,1,0,inf\n"),
            "t.csv:2: column 'ox' (field 1): '1e999' overflows double");
  EXPECT_EQ(csvError(header + "0,0,-5,0,0,1,0,1e400\n"),
            "t.csv:2: column 'tfar' (field 8): '1e400' overflows double");
  EXPECT_EQ(csvError(header + "0,0,-5,0,0,1,0,-1\n"),
            "t.csv:2: column 'tfar' (field 8): must be >= tnear");
  EXPECT_EQ(csvError(header + "\n0,0,-5,0,0,1,2,1\n"),
            "t.csv:3: column 'tfar' (field 8): must be >= tnear");
  EXPECT_EQ(csvError(header + "0,0,-5,0,0,1,-1,1\n"),
            "t.csv:2: column 'tnear' (field 7): must be >= 0");
  // Still accepted: a subnormal direction (strtod's ERANGE for a non-zero result), an
  // empty interval tnear = tfar, tfar = inf.
  std::istringstream ok(header + "0,0,-5,0,0,4.9e-324,0,inf\n0,0,-5,1,0,0,2,2\n");
  const auto rays = algray::query::readRays(ok, "ok.csv");
  ASSERT_EQ(rays.size(), 2u);
  EXPECT_EQ(rays[0].dir.z, std::numeric_limits<double>::denorm_min());
  EXPECT_EQ(rays[1].tnear, 2.0);
  EXPECT_EQ(rays[1].tfar, 2.0);
}

TEST(RayCsv, ByteOrderMarkAndEmptyFile) {
  // Excel's "CSV UTF-8" starts with a byte order mark.
  std::istringstream bom("\xef\xbb\xbfox,oy,oz,dx,dy,dz,tnear,tfar\n0,0,-5,0,0,1,0,inf\n");
  const auto rays = algray::query::readRays(bom, "bom.csv");
  ASSERT_EQ(rays.size(), 1u);
  EXPECT_EQ(rays[0].org, glm::dvec3(0, 0, -5));
  // Only at the start of the file: elsewhere it is part of a field.
  EXPECT_PRED2(startsWith,
               csvError("ox,oy,oz,dx,dy,dz,tnear,tfar\n\xef\xbb\xbf"
                        "0,0,-5,0,0,1,0,inf\n"),
               "t.csv:2: column 'ox' (field 1): not a");
  EXPECT_EQ(csvError(""), "t.csv:1: empty file: expected the header ox,oy,oz,dx,dy,dz,tnear,tfar");
  EXPECT_PRED2(startsWith, csvError("\xef\xbb\xbf"), "t.csv:1: empty file:");
  EXPECT_PRED2(startsWith, csvError("\n\n"), "t.csv:2: empty file:");
  // On the header line after blank lines, where joining files puts it, it is still a mark.
  std::istringstream late("\n\xef\xbb\xbfox,oy,oz,dx,dy,dz,tnear,tfar\n0,0,-5,0,0,1,0,inf\n");
  EXPECT_EQ(algray::query::readRays(late, "late.csv").size(), 1u);
}

// Classic Mac OS text ends its lines in a lone CR: the file was one line ("the header has
// no column 'tfar'"); mixed endings count lines one by one.
TEST(RayCsv, EveryLineEndingEndsALine) {
  for (const std::string eol : {"\r", "\r\n", "\n"}) {
    std::istringstream in("ox,oy,oz,dx,dy,dz,tnear,tfar" + eol + "0,0,-5,0,0,1,0,inf" + eol + eol +
                          "1,0,-5,0,0,1,0,inf" + eol);
    const auto rays = algray::query::readRays(in, "eol.csv");
    ASSERT_EQ(rays.size(), 2u) << int(eol[0]);
    EXPECT_EQ(rays[1].org, glm::dvec3(1, 0, -5));
  }
  EXPECT_EQ(csvError("ox,oy,oz,dx,dy,dz,tnear,tfar\r0,0,-5,0,0,1,0,inf\r\n\n\r0,0,-5,0,0,1,0,-1"),
            "t.csv:5: column 'tfar' (field 8): must be >= tnear");
}

// Quoted fields as RFC 4180 writes them (R's write.csv quotes the header, spreadsheets a text
// column with a comma): "ox" was "the header has no column 'ox'", a quoted comment with a
// comma "expected 9 fields, found 10".
TEST(RayCsv, QuotedFieldsAreRead) {
  std::istringstream in(
      "\"ox\",\"oy\",\"oz\",\"dx\",\"dy\",\"dz\",\"tnear\",\"tfar\",\"note\"\n"
      "0,0,-5,0,0,1,0,inf,\"a, b\"\n"
      " \"1\" ,0,-5,0,0,1,0,\"inf\",\"say \"\"hi\"\", then, go\"\n"
      "2,0,-5,0,0,1,0,inf,\"\"\n");
  const auto rays = algray::query::readRays(in, "q.csv");
  ASSERT_EQ(rays.size(), 3u);
  EXPECT_EQ(rays[0].org, glm::dvec3(0, 0, -5));
  EXPECT_EQ(rays[1].org, glm::dvec3(1, 0, -5));
  EXPECT_TRUE(std::isinf(rays[1].tfar));
  EXPECT_EQ(rays[2].org, glm::dvec3(2, 0, -5));
  const std::string header = "ox,oy,oz,dx,dy,dz,tnear,tfar,note\n";
  EXPECT_EQ(csvError(header + "0,0,-5,0,0,1,0,inf,\"open\n"),
            "t.csv:2: field 9: the quote at character 20 is not closed on its line");
  EXPECT_EQ(csvError(header + "0,0,-5,0,0,1,0,inf,\"a\"b\n"),
            "t.csv:2: field 9: text after its closing quote at character 23");
  EXPECT_EQ(csvError("\"ox,oy,oz,dx,dy,dz,tnear,tfar\n"),
            "t.csv:1: header, field 1: the quote at character 1 is not closed on its line");
  // A quoted number is read as the number; a quoted non-number is named as before.
  EXPECT_EQ(csvError(header + "0,0,-5,0,0,\"x1\",0,inf,\n"),
            "t.csv:2: column 'dz' (field 6): not a number: 'x1'");
  // Spaces and tabs inside the quotes are trimmed as around a plain field, at either end
  // (strtod skipped leading ones only: " 1" was read and "1 " refused); other white space
  // (a form feed, which strtod would skip) stays a non-number.
  std::istringstream spaced(header + "\" 3\",\"4 \",\"\t-5\t\",0,0,1,0,inf,\n");
  const auto spacedRays = algray::query::readRays(spaced, "s.csv");
  ASSERT_EQ(spacedRays.size(), 1u);
  EXPECT_EQ(spacedRays[0].org, glm::dvec3(3, 4, -5));
  EXPECT_EQ(csvError(header + "0,0,-5,0,0,\"\f1\",0,inf,\n"),
            "t.csv:2: column 'dz' (field 6): not a number: '\\x0C1'");
}

// Control bytes in a bad field are shown, not passed on: a NUL cut the message short.
TEST(RayCsv, ControlBytesInAFieldAreShown) {
  const std::string header = "ox,oy,oz,dx,dy,dz,tnear,tfar\n";
  EXPECT_EQ(csvError(header + "0,0,-5,0,0,1" + std::string(1, '\0') + "x,0,inf\n"),
            "t.csv:2: column 'dz' (field 6): not a number: '1\\x00x'");
  EXPECT_EQ(csvError(header + "0,0,-5,0,0,\x7f"
                              "1,0,inf\n"),
            "t.csv:2: column 'dz' (field 6): not a number: '\\x7F1'");
}

// Tabs pad a field as spaces do (a tab-aligned file from a spreadsheet's export), and a
// line of only spaces and tabs is blank, as an empty one is.
TEST(RayCsv, TabsAndBlankLinesOfSpaces) {
  std::istringstream in(
      "\tox\t,\toy,oz , dx,dy,dz,tnear,tfar\n"
      "\t1\t,2,3,0,0,1,0,inf\n"
      "  \t \n"
      "\t\n"
      "4, 5 ,\t6,0,0,1,0,inf\n");
  const auto rays = algray::query::readRays(in, "tabs.csv");
  ASSERT_EQ(rays.size(), 2u);
  EXPECT_EQ(rays[0].org, glm::dvec3(1, 2, 3));
  EXPECT_EQ(rays[1].org, glm::dvec3(4, 5, 6));
}

// Every row has the header's field count: a row with one more field is refused (an extra
// value would else be silently dropped), and a line is counted from the start of the file
// also for the header (the third line here, after two blank ones).
TEST(RayCsv, FieldCountAndHeaderLine) {
  const std::string header = "ox,oy,oz,dx,dy,dz,tnear,tfar\n";
  EXPECT_EQ(csvError(header + "0,0,-5,0,0,1,0,inf,7\n"), "t.csv:2: expected 8 fields, found 9");
  EXPECT_EQ(csvError("\n\nox,oy,oz,dx,dy,tnear,tfar\n0,0,-5,0,0,0,inf\n"),
            "t.csv:3: the header has no column 'dz' (need ox,oy,oz,dx,dy,dz,tnear,tfar in any "
            "order)");
}

// Other columns are ignored, also those whose name begins with a column's ("oxygen",
// "tfar_old"): only the exact name is the column.
TEST(RayCsv, ColumnsAreNamedExactly) {
  std::istringstream in("oxygen,ox,oy,oz,dx,dy,dz,tnear,tfar,tfar_old\n9,1,2,3,0,0,1,0,inf,-1\n");
  const auto rays = algray::query::readRays(in, "names.csv");
  ASSERT_EQ(rays.size(), 1u);
  EXPECT_EQ(rays[0].org, glm::dvec3(1, 2, 3));
  EXPECT_TRUE(std::isinf(rays[0].tfar));
}

// Only tfar may be infinite, and only +inf (tools.md: "every value is finite but tfar,
// which may be inf"): tnear = inf is no interval start even with tfar = inf, and tfar =
// -inf is named as not finite, not as an interval that ends before it starts.
TEST(RayCsv, OnlyTfarMayBeInfinite) {
  const std::string header = "ox,oy,oz,dx,dy,dz,tnear,tfar\n";
  EXPECT_EQ(csvError(header + "0,0,-5,0,0,1,inf,inf\n"),
            "t.csv:2: column 'tnear' (field 7): must be finite: 'inf'");
  EXPECT_EQ(csvError(header + "0,0,-5,0,0,1,0,-inf\n"),
            "t.csv:2: column 'tfar' (field 8): must be finite: '-inf'");
}

// OUT.csv as tools.md gives it: the header hit,t,nx,ny,nz, one row per hit in order, zeros
// on a miss, numbers as %.17g prints them, so that strtod gives every double back bit for
// bit (a user computes hit points o + t d from them and traces rays from there). 0.1 + 0.2
// is 0.30000000000000004 (15 digits print 0.3), and the components of (1, 2, 3) / sqrt(14)
// need 17 digits too.
TEST(RayCsv, HitsRoundTripThroughTheirText) {
  std::vector<algray::query::QueryHit> hits(3);
  hits[0].hit = true;
  hits[0].t = 0.1 + 0.2;
  hits[0].normal = glm::dvec3(1, 2, 3) / std::sqrt(14.0);
  hits[2].hit = true;
  hits[2].t = 1e-300 / 3;
  hits[2].normal = glm::dvec3(-1, 1, -1) / std::sqrt(3.0);
  std::ostringstream out;
  algray::query::writeHits(out, hits);
  std::istringstream text(out.str());
  std::string line;
  ASSERT_TRUE(std::getline(text, line));
  EXPECT_EQ(line, "hit,t,nx,ny,nz");
  for (const auto& h : hits) {
    ASSERT_TRUE(std::getline(text, line));
    if (!h.hit) {
      EXPECT_EQ(line, "0,0,0,0,0");
      continue;
    }
    std::vector<double> v;
    std::istringstream fields(line);
    std::string field;
    while (std::getline(fields, field, ',')) v.push_back(std::strtod(field.c_str(), nullptr));
    ASSERT_EQ(v.size(), 5u) << line;
    EXPECT_EQ(v[0], 1.0) << line;
    EXPECT_EQ(v[1], h.t) << line;
    EXPECT_EQ(v[2], h.normal.x) << line;
    EXPECT_EQ(v[3], h.normal.y) << line;
    EXPECT_EQ(v[4], h.normal.z) << line;
  }
  EXPECT_FALSE(std::getline(text, line)) << "one row per hit: " << line;
}

}  // namespace
