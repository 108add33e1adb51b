// Tests of include/algray/jsurf.h: the Java properties syntax on hand-written inputs, and
// every real SURFER file in ../shared/gallery/jsurf/ against a direct long double
// evaluation of its equation text (tests/support/direct_eval.h).
#include "algray/jsurf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>

#include "support/direct_eval.h"

namespace algray {
namespace {

std::string expectError(const std::function<void()>& f) {
  try {
    f();
  } catch (const ParseError& e) {
    ADD_FAILURE() << "ParseError escaped: " << e.what();
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error";
  return {};
}

TEST(Jsurf, PropertiesSyntax) {
  const std::string text =
      "# comment = ignored\n"
      "   ! another comment\n"
      "\n"
      "plain=1.0 2.0\n"
      "colon: value with spaces  \n"
      "spaced   =   padded\n"
      "blank_sep value\n"
      "esc\\:aped\\=key=a\\tb\\\\c\\u0041\n"
      "continued=1 \\\n"
      "     2 \\\n"
      "  3\n"
      "crlf=x\r\n"
      "empty=\n"
      "dup=first\n"
      "dup=second\n";
  const JsurfFile f = JsurfFile::parse(text, "t.jsurf");
  EXPECT_EQ(f.name(), "t.jsurf");
  EXPECT_FALSE(f.has("#"));
  EXPECT_FALSE(f.has("!"));
  EXPECT_EQ(f.get("plain"), "1.0 2.0");
  EXPECT_EQ(f.get("colon"), "value with spaces  ");
  EXPECT_EQ(f.get("spaced"), "padded");
  EXPECT_EQ(f.get("blank_sep"), "value");
  EXPECT_EQ(f.get("esc:aped=key"), "a\tb\\cA");
  EXPECT_EQ(f.get("continued"), "1 2 3");
  EXPECT_EQ(f.get("crlf"), "x");
  EXPECT_EQ(f.get("empty"), "");
  EXPECT_EQ(f.get("dup"), "second");
  EXPECT_FALSE(f.get("missing").has_value());
  EXPECT_EQ(f.lineOf("plain"), 4);
  EXPECT_EQ(f.lineOf("continued"), 9);
  EXPECT_EQ(f.lineOf("missing"), 0);
  EXPECT_EQ(f.getNumbers("continued"), (std::vector<double>{1, 2, 3}));
  EXPECT_EQ(f.getNumber("missing", 7.5), 7.5);
  EXPECT_EQ(f.getNumbers("plain", 2), (std::vector<double>{1.0, 2.0}));
}

// The corners of java.util.Properties.load that a SURFER file can reach (a mutation round
// of session 56 changed each without a test failing): an even number of trailing
// backslashes is escaped backslashes, not a continuation; a continuation line is never a
// comment, whatever it starts with; \f is a form feed; and a backslash on the last line of
// a file without a final newline is dropped, the line kept.
TEST(Jsurf, PropertiesSyntaxCorners) {
  const JsurfFile f = JsurfFile::parse(
      "even=a\\\\\\\\\n"
      "next=b\n"
      "cont=1 \\\n"
      "   #2 \\\n"
      "  !3\n"
      "ff=a\\fb\n"
      "last=x\\",
      "t.jsurf");
  EXPECT_EQ(f.get("even"), "a\\\\");
  EXPECT_EQ(f.get("next"), "b");
  EXPECT_EQ(f.get("cont"), "1 #2 !3");
  EXPECT_FALSE(f.has("#2"));
  EXPECT_EQ(f.get("ff"), "a\fb");
  EXPECT_EQ(f.get("last"), "x");
}

// An editor's UTF-8 byte order mark is not part of the first key (the file had "no
// surface_equation"); the columns of the first line count from after it.
// A directory is named as such (an ifstream opens it and reads nothing: it was an empty
// file, which then failed later for want of a surface_equation).
TEST(Jsurf, ADirectoryIsNamedAsSuch) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path();
  try {
    JsurfFile::read(dir);
    ADD_FAILURE() << "a directory was read as a file";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("is a directory"), std::string::npos) << e.what();
  }
}

TEST(Jsurf, ByteOrderMarkIsSkipped) {
  const JsurfFile f = JsurfFile::parse("\xEF\xBB\xBFsurface_equation=x^2+y^2+z^2-1+\n", "t.jsurf");
  ASSERT_TRUE(f.has("surface_equation"));
  try {
    f.polynomial();
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("t.jsurf:1:32:"), std::string::npos) << e.what();
  }
}

TEST(Jsurf, NumberErrorsCarryFileAndLine) {
  const JsurfFile f = JsurfFile::parse("a=1 2 x\nb=1.0E-4 2\nc=1 2 3\n", "n.jsurf");
  EXPECT_NE(
      expectError([&] { f.getNumbers("a"); }).find("n.jsurf:1: a: 'x' is not a finite number"),
      std::string::npos);
  EXPECT_EQ(f.getNumbers("b"), (std::vector<double>{1e-4, 2.0}));
  EXPECT_NE(expectError([&] {
              f.getNumbers("c", 16);
            }).find("n.jsurf:3: c: expected 16 numbers, found 3"),
            std::string::npos);
  EXPECT_NE(expectError([&] { f.getNumber("c", 0.0); }).find("expected 1 numbers"),
            std::string::npos);
  EXPECT_NE(expectError([&] { f.getNumbers("zz"); }).find("missing key 'zz'"), std::string::npos);
  EXPECT_NE(expectError([] {
              JsurfFile::parse("k=\\u12\n", "u.jsurf");
            }).find("u.jsurf:1: malformed \\uXXXX"),
            std::string::npos);
  EXPECT_NE(expectError([] { JsurfFile::parse("k=\\uZZZZ\n", "u.jsurf"); }).find("malformed"),
            std::string::npos);
  EXPECT_NE(expectError([] { JsurfFile::read("/nonexistent/dir/f.jsurf"); }).find("cannot read"),
            std::string::npos);
  // One sign only, as Java's Double.parseDouble: "+-2" and "++2" are not numbers.
  const JsurfFile signs = JsurfFile::parse("a=+-2\nb=++2\nc=+2 -2\n", "s.jsurf");
  EXPECT_NE(expectError([&] { signs.getNumbers("a"); }).find("s.jsurf:1: a: '+-2' is not a finite"),
            std::string::npos);
  EXPECT_NE(expectError([&] { signs.getNumbers("b"); }).find("'++2' is not a finite number"),
            std::string::npos);
  EXPECT_EQ(signs.getNumbers("c"), (std::vector<double>{2.0, -2.0}));
  // Below half the smallest subnormal (2^-1075 ~ 2.47e-324) a number rounds to +-0, as in
  // Java and in the equation's literals; only overflow is refused.
  const JsurfFile tiny = JsurfFile::parse("t=1e-400 -1e-400 1e-5000 3e-324\nh=1e400\n", "t.jsurf");
  const std::vector<double> t = tiny.getNumbers("t");
  ASSERT_EQ(t.size(), 4u);
  EXPECT_EQ(t[0], 0.0);
  EXPECT_TRUE(t[1] == 0.0 && std::signbit(t[1]));
  EXPECT_EQ(t[2], 0.0);
  EXPECT_EQ(t[3], std::numeric_limits<double>::denorm_min());  // 3e-324 > 2^-1075
  EXPECT_NE(expectError([&] { tiny.getNumbers("h"); }).find("t.jsurf:2: h: '1e400' is not"),
            std::string::npos);
}

// Java strings are UTF-16, so java.util.Properties escapes a character beyond U+FFFF as a
// surrogate pair: it is one character, whose UTF-8 form is the 4 bytes of RFC 3629
// (U+1F600 = F0 9F 98 80). A lone surrogate has no UTF-8 form: U+FFFD (EF BF BD).
TEST(Jsurf, SurrogatePairsBecomeOneCharacter) {
  const JsurfFile f = JsurfFile::parse(
      "pair=\\uD83D\\uDE00!\nlone=\\uD83Dx\\uDE00\nsurface_equation=\\uD83D\\uDE00 + q\n",
      "p.jsurf");
  EXPECT_EQ(f.get("pair"), "\xF0\x9F\x98\x80!");
  EXPECT_EQ(f.get("lone"), "\xEF\xBF\xBDx\xEF\xBF\xBD");
  // One character, shown whole in the message, at the column of its escape.
  EXPECT_NE(expectError([&] {
              f.polynomial();
            }).find("p.jsurf:3:18: unexpected character '\xF0\x9F\x98\x80'"),
            std::string::npos);
}

TEST(Jsurf, EquationErrorsPointIntoTheFile) {
  // 'q' is value column 7; the value starts at file column 18.
  const JsurfFile a = JsurfFile::parse("# c\nsurface_equation=x^2 + q\n", "a.jsurf");
  EXPECT_NE(expectError([&] { a.polynomial(); }).find("a.jsurf:2:24: unknown name 'q'"),
            std::string::npos);
  // Across a continuation the location follows the physical line.
  const JsurfFile b = JsurfFile::parse("surface_equation=x^2 + \\\n      y^2 + q\n", "b.jsurf");
  EXPECT_NE(expectError([&] { b.polynomial(); }).find("b.jsurf:2:13: unknown name 'q'"),
            std::string::npos);
  // At the end of the value: one past its last character.
  const JsurfFile c = JsurfFile::parse("surface_equation = (x+1\n", "c.jsurf");
  EXPECT_NE(expectError([&] {
              c.polynomial();
            }).find("c.jsurf:1:20: unbalanced parenthesis: '(' is never closed"),
            std::string::npos);
  // A second place in the message is the file's too (it was the equation's "column 3" after
  // the file's "1:20"), here across a continuation.
  const JsurfFile c2 = JsurfFile::parse("surface_equation=x + (y \\\n  = 1)\n", "c2.jsurf");
  EXPECT_EQ(expectError([&] { c2.polynomial(); }),
            "c2.jsurf:2:3: expected ')' to close '(' at line 1, column 22 but found '='");
  const JsurfFile d = JsurfFile::parse("surface_equation=x^3\n", "d.jsurf");
  EXPECT_NE(
      expectError([&] { d.polynomial(2); }).find("d.jsurf:1:19: degree 3 exceeds the limit 2"),
      std::string::npos);
  EXPECT_NE(expectError([] {
              JsurfFile::parse("a=1\n", "e.jsurf").polynomial();
            }).find("e.jsurf: no surface_equation"),
            std::string::npos);
  const JsurfFile g =
      JsurfFile::parse("surface_parameter_a=abc\nsurface_equation=x+a\n", "g.jsurf");
  EXPECT_NE(expectError([&] {
              g.polynomial();
            }).find("g.jsurf:1: surface_parameter_a: 'abc' is not a finite number"),
            std::string::npos);
  // A parameter without a name, at its line.
  const JsurfFile unnamed =
      JsurfFile::parse("surface_equation=x^2+y^2-1\nsurface_parameter_=1\n", "u.jsurf");
  EXPECT_NE(expectError([&] {
              unnamed.polynomial();
            }).find("u.jsurf:2: surface_parameter_: a parameter needs a name"),
            std::string::npos);
  // A parameter named after a built-in is reported at its own line, not in the equation.
  const JsurfFile h =
      JsurfFile::parse("surface_equation=x^2+y^2-1\n\nsurface_parameter_x=1\n", "h.jsurf");
  EXPECT_NE(expectError([&] {
              h.polynomial();
            }).find("h.jsurf:3: surface_parameter_x: clashes with the built-in name 'x'"),
            std::string::npos);
}

TEST(Jsurf, ParametersFeedTheEquation) {
  const JsurfFile f = JsurfFile::parse(
      "surface_parameter_b=0.5\nsurface_parameter_a=0.25\nsurface_equation=(x^2+y^2+z^2+a^2-b^2)^2-"
      "4*b^2*(x^2+y^2)\n");
  const auto p = f.parameters();
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p.at("a"), 0.25);
  EXPECT_EQ(p.at("b"), 0.5);
  const Polynomial torus = f.polynomial();
  EXPECT_EQ(torus.degree(), 4);
  EXPECT_EQ(torus.coeff(0, 0, 0), std::pow(0.25 * 0.25 - 0.5 * 0.5, 2));
}

// Every real file: it reads, has an equation, and the expansion agrees with a direct
// evaluation of the equation text; the degree agrees with the growth of the direct
// evaluation along random directions (d = log10 f(1e4 p) / f(1e3 p)).
TEST(Jsurf, EveryRealGalleryFile) {
  const std::filesystem::path dir = ALGRAY_SHARED_DIR "/gallery/jsurf";
  ASSERT_TRUE(std::filesystem::is_directory(dir)) << dir;
  int files = 0;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".jsurf") continue;
    ++files;
    SCOPED_TRACE(entry.path().filename().string());
    const JsurfFile file = JsurfFile::read(entry.path());
    const auto text = file.get("surface_equation");
    ASSERT_TRUE(text.has_value());
    EXPECT_GT(file.lineOf("surface_equation"), 0);
    EXPECT_EQ(file.getNumbers("rotation_matrix", 16).size(), 16u);
    EXPECT_TRUE(std::isfinite(file.getNumber("scale_factor", NAN)));  // a log scale, may be < 0
    Polynomial f;
    ASSERT_NO_THROW(f = file.polynomial());
    ASSERT_TRUE(f.isFinite());
    test::DirectEvaluator direct(*text, file.parameters());
    for (int i = 0; i < 30; ++i) {
      const glm::dvec3 p(u(rng), u(rng), u(rng));
      const auto e = f.evaluateWithBound(p);
      const long double ref = direct(p.x, p.y, p.z);
      ASSERT_FALSE(std::isnan(static_cast<double>(ref)));
      EXPECT_LE(std::abs(static_cast<double>(ref - e.value)),
                1e-12 * e.magnitude + 4 * e.valueError);
    }
    int degree = -1;
    for (int i = 0; i < 5; ++i) {
      const glm::dvec3 p(u(rng), u(rng), u(rng));
      const long double far = direct(1e4L * p.x, 1e4L * p.y, 1e4L * p.z);
      const long double near = direct(1e3L * p.x, 1e3L * p.y, 1e3L * p.z);
      degree = std::max(
          degree,
          static_cast<int>(std::lround(std::log10(std::abs(static_cast<double>(far / near))))));
    }
    EXPECT_EQ(f.degree(), degree);
  }
  EXPECT_GE(files, 20);
}

}  // namespace
}  // namespace algray
