// Tests of include/algray/parser.h against independent references: a direct long double
// evaluation of the text (tests/support/direct_eval.h), closed forms, MPFR expansions of
// the same double literals, and Polynomial::toString() round trips.
#include "algray/parser.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "support/direct_eval.h"
#include "support/mp.h"

namespace algray {
namespace {

using test::DirectEvaluator;
using test::Mp;

// Compares the expanded polynomial with the direct evaluation of the text at random
// points. The tolerance is relative to the sum of |terms| of the expansion (the scale of
// its own rounding), so it fails for any wrong or missing coefficient.
void expectMatchesDirect(const std::string& text, const ParseOptions& options = {},
                         double radius = 1.5) {
  SCOPED_TRACE(text);
  const Polynomial f = parsePolynomial(text, options);
  DirectEvaluator direct(text, options.parameters);
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(-radius, radius);
  for (int i = 0; i < 50; ++i) {
    const glm::dvec3 p(u(rng), u(rng), u(rng));
    const auto e = f.evaluateWithBound(p);
    const long double ref = direct(p.x, p.y, p.z);
    ASSERT_FALSE(std::isnan(static_cast<double>(ref)));
    EXPECT_LE(std::abs(static_cast<double>(ref - e.value)), 1e-12 * e.magnitude + 4 * e.valueError)
        << "at " << p.x << " " << p.y << " " << p.z;
  }
}

TEST(Parser, ExpandsClassicEquations) {
  for (const char* text : {
           "x^2 + y^2 + z^2 - 1",
           "(x^2+y^2+z^2+0.84)^2 - 4*(x^2+y^2)",
           "4*((1+sqrt(5))/2)^2*x^2 - y^2",
           "(x^2 + 9/4*y^2 + z^2 - 1)^3 - x^2*z^3 - 9/80*y^2*z^3",
           "(x*y - z^3 - 1)^2 - (1 - x^2 - y^2)^3",
           "60*(x^2+y^2)*z^4 - (60 - x^2 - y^2 - z^2)^3",
           "(x+y+z+1)^12",
           "(x - 2*y + 0.5*z - 3)^7 * (x*y*z - 1)^2",
           "x^2 = y*z + 1",
           "(x^2+y^2+z^2)^20",
       })
    expectMatchesDirect(text);
}

TEST(Parser, ParametersAndConstants) {
  ParseOptions o;
  o.parameters = {{"a", 0.5}, {"b", 0.25}, {"R", 1.0}, {"r", 0.4}};
  expectMatchesDirect("(x^2+y^2+z^2+R^2-r^2)^2 = 4*R^2*(x^2+y^2)", o);
  expectMatchesDirect(
      "(x^2+y^2+z^2-1*(0.5+2*a)^2)^2-1*(3.0*((0.5+2*a)^2)-1*1.0)/(3.0-1*((0.5+2*a)^2))"
      "*(1-1*z-1*sqrt(2)*x)*(1-1*z+sqrt(2)*x)*(1+z+sqrt(2)*y)*(1+z-1*sqrt(2)*y)",
      o);
  expectMatchesDirect("pi*x + e*y - sin(pi/6)*z + cos(0)*exp(1)*log(2)*tan(1) + abs(-3)*ln(e)*x*y",
                      o);
  // Folded constants are the libm values, as the text asks.
  const Polynomial f = parsePolynomial("sqrt(2)*x + pi*y + e*z");
  EXPECT_EQ(f.coeff(1, 0, 0), std::sqrt(2.0));
  EXPECT_EQ(f.coeff(0, 1, 0), M_PI);
  EXPECT_EQ(f.coeff(0, 0, 1), M_E);
}

TEST(Parser, LiteralsWhitespaceAndPrecedence) {
  // Literals read with correct rounding, quotients of constants in double.
  EXPECT_EQ(parsePolynomial(".5*x").coeff(1, 0, 0), 0.5);
  EXPECT_EQ(parsePolynomial("1e-3*x").coeff(1, 0, 0), 1e-3);
  EXPECT_EQ(parsePolynomial("2.5E+2*x").coeff(1, 0, 0), 250.0);
  EXPECT_EQ(parsePolynomial("24/7").coeff(0, 0, 0), 24.0 / 7.0);
  EXPECT_EQ(parsePolynomial("1.").coeff(0, 0, 0), 1.0);
  EXPECT_EQ(parsePolynomial("0.1*x").coeff(1, 0, 0), 0.1);
  // Division of a polynomial is coefficient by coefficient (x/3 is 1/3 exactly rounded).
  EXPECT_EQ(parsePolynomial("2*x/3").coeff(1, 0, 0), 2.0 / 3.0);
  // Whitespace anywhere (real files write "y ^2").
  EXPECT_EQ(parsePolynomial("  x ^2 +\ty ^ 2\n- 1 "), parsePolynomial("x^2+y^2-1"));
  // Windows line ends, form feeds and vertical tabs too (C's isspace set).
  EXPECT_EQ(parsePolynomial("x ^2 +\r\ny ^ 2\f-\v1\r\n"), parsePolynomial("x^2+y^2-1"));
  // Exponent forms: ^2, ^(1+1), ^2.0 and ** are the same power.
  const Polynomial x2 = parsePolynomial("x*x");
  for (const char* t : {"x^2", "x^(1+1)", "x^2.0", "x**2", "x^ +2"})
    EXPECT_EQ(parsePolynomial(t), x2) << t;
  // -x^2 = -(x^2); 2^-1 = 1/2; ^ is right-associative; unary minus after an operator.
  EXPECT_EQ(parsePolynomial("-x^2").coeff(2, 0, 0), -1.0);
  EXPECT_EQ(parsePolynomial("-2^2").coeff(0, 0, 0), -4.0);
  EXPECT_EQ(parsePolynomial("2^-1*x").coeff(1, 0, 0), 0.5);
  EXPECT_EQ(parsePolynomial("x^2^3").degree(), 8);
  EXPECT_EQ(parsePolynomial("x*-y").coeff(1, 1, 0), -1.0);
  EXPECT_EQ(parsePolynomial("x - -y").coeff(0, 1, 0), 1.0);
  // Real powers of constants are fine.
  EXPECT_EQ(parsePolynomial("2^0.5*x").coeff(1, 0, 0), std::pow(2.0, 0.5));
  // lhs = rhs means lhs - rhs.
  EXPECT_EQ(parsePolynomial("x^2 = y"), parsePolynomial("x^2 - y"));
  // Underflowing literals round to zero like any other literal.
  EXPECT_EQ(parsePolynomial("1e-400*x + 1"), Polynomial(1.0));
}

// Random polynomials of every storage shape: toString() then parse gives the same
// coefficients bit for bit.
TEST(Parser, RoundTripsToString) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0), keep(0.0, 1.0);
  std::uniform_int_distribution<int> exponent(-30, 30);
  for (int trial = 0; trial < 60; ++trial) {
    const int degree = trial < 50 ? trial % 13 : 40;
    const double density = trial < 50 ? 0.7 : 0.02;
    Polynomial f;
    for (int n = 0; n <= degree; ++n)
      forEachMonomialOfDegree(n, [&](int i, int j, int k, int) {
        if (keep(rng) < density || (n == degree && i == n))
          f.setCoeff(i, j, k, std::ldexp(mantissa(rng), exponent(rng)));
      });
    const std::string text = f.toString();
    const Polynomial g = parsePolynomial(text);
    ASSERT_EQ(g.degree(), f.degree()) << text.substr(0, 200);
    for (size_t m = 0; m < f.coeffs().size(); ++m) ASSERT_EQ(g.coeffs()[m], f.coeffs()[m]) << m;
  }
  EXPECT_TRUE(parsePolynomial(Polynomial().toString()).isZero());
}

// ---- Pruning of rounding junk ------------------------------------------------------

// Exact expansion of prod (a_i x + b_i) with double a_i, b_i, rounded per coefficient.
std::vector<double> mpExpandLinear(const std::vector<std::pair<double, double>>& factors) {
  std::vector<Mp> c{Mp(1.0)};
  for (const auto& [a, b] : factors) {
    std::vector<Mp> next(c.size() + 1);
    for (size_t i = 0; i < c.size(); ++i) {
      next[i] += c[i] * Mp(b);
      next[i + 1] += c[i] * Mp(a);
    }
    c = next;
  }
  std::vector<double> out;
  for (const Mp& v : c) out.push_back(v.toDouble());
  return out;
}

std::string literal(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "(%.17g)", v);
  return buf;
}

TEST(Parser, PrunesJunkToExactZero) {
  EXPECT_TRUE(parsePolynomial("(x+0.1)^2 - x^2 - 0.2*x - 0.01").isZero());
  EXPECT_TRUE(parsePolynomial("(sqrt(2)*x)^2 - 2*x^2").isZero());
  EXPECT_TRUE(parsePolynomial("sin(pi)*x").isZero());
  // Junk does not count towards the degree limit: the true degree here is 0.
  EXPECT_TRUE(parsePolynomial("((sqrt(2)*x)^2 - 2*x^2)^21 + 0").isZero());
  // A product of random binomials minus its correctly rounded expansion written out is
  // zero up to rounding only; the parser must return exactly zero.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (int trial = 0; trial < 40; ++trial) {
    std::vector<std::pair<double, double>> factors;
    std::string product, expanded;
    const int n = 2 + trial % 7;
    for (int i = 0; i < n; ++i) {
      factors.emplace_back(u(rng), u(rng));
      product += (i ? "*(" : "(") + literal(factors.back().first) + "*x+" +
                 literal(factors.back().second) + ")";
    }
    const auto c = mpExpandLinear(factors);
    for (size_t k = 0; k < c.size(); ++k)
      expanded += " + " + literal(c[k]) + "*x^" + std::to_string(k);
    EXPECT_TRUE(parsePolynomial(product + " - (" + expanded + ")").isZero()) << product;
    // A real small term survives the same cancellation.
    const Polynomial g = parsePolynomial(product + " - (" + expanded + ") + 1e-9*y");
    EXPECT_EQ(g.nonZeroCount(), 1) << product;
    EXPECT_EQ(g.coeff(0, 1, 0), 1e-9);
  }
}

TEST(Parser, KeepsRealSmallCoefficients) {
  // (x + d)^3 - x^3 = 3d x^2 + 3d^2 x + d^3 with d = double(1e-8): all three are real.
  const Polynomial f = parsePolynomial("(x+1e-8)^3 - x^3");
  const Mp d(1e-8);
  EXPECT_NEAR(f.coeff(2, 0, 0), (Mp(3.0) * d).toDouble(), 1e-15 * 3e-8);
  EXPECT_NEAR(f.coeff(1, 0, 0), (Mp(3.0) * d * d).toDouble(), 1e-15 * 3e-16);
  EXPECT_NEAR(f.coeff(0, 0, 0), (d * d * d).toDouble(), 1e-15 * 1e-24);
  EXPECT_EQ(f.coeff(3, 0, 0), 0.0);
  // Cancellation of large terms leaving a small exact one.
  EXPECT_EQ(parsePolynomial("(1e8*x+1)^2 - 1e16*x^2 - 2e8*x"), Polynomial(1.0));
  // Powers of binomials with tiny and huge constants: every coefficient agrees with the
  // exact expansion of the same doubles (nothing real is dropped).
  for (double b : {1e-8, 3.7e-5, 0.1, 7.0, 1e6}) {
    for (int n : {2, 5, 10, 17}) {
      const Polynomial g = parsePolynomial("(x + " + literal(b) + ")^" + std::to_string(n));
      const auto c = mpExpandLinear(std::vector<std::pair<double, double>>(n, {1.0, b}));
      for (int k = 0; k <= n; ++k)
        EXPECT_NEAR(g.coeff(k, 0, 0), c[k], 1e-14 * std::abs(c[k]))
            << "b=" << b << " n=" << n << " k=" << k;
    }
  }
}

// ---- Rejections: column and message ---------------------------------------------------

struct Rejection {
  const char* text;
  int column;
  const char* message;  // a substring of ParseError::message()
};

void expectRejected(const Rejection& r, const ParseOptions& options = {}) {
  try {
    parsePolynomial(r.text, options);
    ADD_FAILURE() << "accepted: " << r.text;
  } catch (const ParseError& e) {
    EXPECT_EQ(e.column(), r.column) << r.text << " -> " << e.message();
    EXPECT_NE(e.message().find(r.message), std::string::npos) << r.text << " -> " << e.message();
    EXPECT_NE(std::string(e.what()).find("column " + std::to_string(r.column)), std::string::npos);
  }
}

TEST(Parser, RejectsWithColumnAndMessage) {
  const Rejection cases[] = {
      // Not a polynomial.
      {"x^0.5", 3, "exponent must be a non-negative integer"},
      {"y + x^-1", 7, "exponent must be a non-negative integer"},
      {"(x-x)^0.5", 7, "exponent must be a non-negative integer"},
      {"2^x", 3, "exponent must be a constant"},
      {"1 + sin(x)", 5, "sin() of an expression in x, y, z is not a polynomial"},
      {"sqrt(x^2)", 1, "sqrt() of an expression in x, y, z is not a polynomial"},
      {"y/(x+1)", 3, "division by an expression in x, y, z is not a polynomial"},
      {"y/(x-x+1)", 3, "division by an expression in x, y, z"},
      {"y/x^0", 3, "division by an expression in x, y, z"},
      // Names.
      {"x + q", 5, "unknown name 'q'"},
      {"2*xy + 1", 3, "unknown name 'xy' (write products with '*'"},
      {"x2 + 1", 1, "unknown name 'x2'"},
      {"foo(2)*x", 1, "unknown function 'foo'"},
      {"sin x", 1, "needs an argument in parentheses"},
      // Degree.
      {"(x^2+y^2)^23", 10, "degree 46 exceeds the limit 40"},
      {"(x+y)^20*(x+z)^21", 9, "degree 41 exceeds the limit 40"},
      {"x^1e300", 2, "exceeds the degree limit 40"},
      // Non-finite.
      {"x*1e400", 3, "too large for double"},
      {"1/0 + x", 3, "division by zero"},
      {"x/(0.1*3-0.3)", 3, "division by zero"},
      {"0^-1 + x", 2, "division by zero"},
      {"sqrt(-1)*x", 1, "sqrt(-1) is not a finite real number"},
      {"log(0)", 1, "log(0) is not a finite real number"},
      {"exp(1000)*x", 1, "not finite"},
      {"(-8)^(1/3)", 5, "not real"},
      {"(1e200*x)^2", 10, "coefficient overflow"},
      {"1e300*1e300 + x", 6, "not finite"},
      // Structure.
      {"", 1, "empty equation"},
      {"  \t ", 1, "empty equation"},
      {"(x+1", 1, "unbalanced parenthesis: '(' is never closed"},
      {"((x+1)*(y", 8, "unbalanced parenthesis: '(' is never closed"},
      {"x+1)", 4, "unbalanced parenthesis: ')' has no matching '('"},
      {"(x = 1)", 4, "expected ')' to close '(' at column 1"},
      {"()", 2, "empty parentheses"},
      {"x +", 4, "the equation ends after '+'"},
      {"x * * y", 5, "expected a number, a name or '('"},
      {"= x", 1, "missing left-hand side"},
      {"x =", 3, "missing right-hand side"},
      {"x = 1 = 2", 7, "only one '='"},
      {"x y", 3, "missing operator before 'y'"},
      {"2x + 1", 1, "malformed number '2x' (write a product with '*': 2*x)"},
      {"z - 3y^2", 5, "malformed number '3y' (write a product with '*': 3*y)"},
      {"2xz + 1", 1, "malformed number '2xz' (write a product with '*': 2*x*z)"},
      {"2pi*x", 1, "malformed number '2pi' (write a product with '*': 2*pi)"},
      {"1.2.3", 1, "malformed number '1.2.3' (a number has one decimal point"},
      {"x - 1e0.5", 5, "malformed number '1e0.5' (a number has one decimal point"},
      {"X^2 + y", 1, "unknown name 'X' (the coordinates are x, y, z, in lower case)"},
      {"x^2 == 1", 6, "'==' is written '=' here"},
      {"x = = 1", 5, "expected a number, a name or '(' but found '='"},
      {"x^2 + y^2 <= 1", 11, "unexpected character '<' (a surface is an equation"},
      {"x + 2e", 5, "malformed number '2e'"},
      {"x # y", 3, "unexpected character '#'"},
      {"x + [y]", 5, "unexpected character '['"},
      // Each bracket and the comma with its own hint: braces group as brackets do, a closing
      // one is pointed at ')', a comma is an argument list's or a decimal comma.
      {"{x + 1}^2", 1, "unexpected character '{' (use '(' for grouping)"},
      {"(x + 1]^2", 7, "unexpected character ']' (use ')' for grouping)"},
      {"(x + 1}^2", 7, "unexpected character '}' (use ')' for grouping)"},
      {"sqrt(2, 3)*x", 7, "unexpected character ',' (functions take one argument; write decimals"},
      {"1,5*x", 2, "unexpected character ',' (functions take one argument; write decimals"},
      // A point that no digit follows is no number (".5" is one): the character, not a
      // "malformed number '.'".
      {"x . y", 3, "unexpected character '.'"},
      {"x\xe2\x81\xbb + 1", 2, "unexpected character '\xe2\x81\xbb'"},  // x⁻ alone
      {"\xc3\xa9 \xc3\xa9 ?", 1, "unexpected character"},
  };
  for (const Rejection& r : cases) expectRejected(r);
}

// A message names at most one place besides its own column, and says which: the two
// parenthesis messages are about the parenthesis at the error's column (they repeated it
// as "at column N", which a scene file's "file:2:36:" prefix then contradicted), and the
// one that names a second place gives its column so that callers can write it their way.
TEST(Parser, SecondPlaceInAMessageIsItsOwnColumn) {
  auto errorOf = [](std::string_view text) {
    try {
      parsePolynomial(text);
    } catch (const ParseError& e) {
      return e;
    }
    return ParseError(0, "no error");
  };
  for (const char* text : {"(x+1", "x+1)", "((x+1)*(y"}) {
    const ParseError e = errorOf(text);
    EXPECT_EQ(e.message().find("column"), std::string::npos) << text << ": " << e.message();
    EXPECT_EQ(e.relatedColumn(), 0) << text;
    EXPECT_EQ(e.messageWith("elsewhere"), e.message()) << text;
  }
  const ParseError e = errorOf("x + (y = 1)");
  EXPECT_EQ(e.column(), 8);
  EXPECT_EQ(e.relatedColumn(), 5);
  EXPECT_EQ(e.message(), "expected ')' to close '(' at column 5 but found '='");
  EXPECT_EQ(std::string(e.what()), "column 8: " + e.message());
  EXPECT_EQ(e.messageWith("line 2, column 30"),
            "expected ')' to close '(' at line 2, column 30 but found '='");
}

// Equations copied from papers and web pages: superscript exponents, the minus sign U+2212
// and the en dash U+2013, dot and cross operators, the division sign, no-break and thin
// spaces, and the letter pi read as the ASCII forms, bit for bit; errors still point at the
// character as written.
TEST(Parser, TypographicFormsReadAsTheirSymbols) {
  const std::pair<const char*, const char*> same[] = {
      {"x²+y²+z²−1", "x^2+y^2+z^2-1"},
      {"(x² + y² + z² + R² − r²)² = 4·R²·(x² + y²)", "(x^2+y^2+z^2+R^2-r^2)^2 = 4*R^2*(x^2+y^2)"},
      {"x¹⁰ − y⁹ + z⁸·x⁷ − y⁶⋅z⁵ + x⁴∙y³ + z¹ − 2⁰", "x^10-y^9+z^8*x^7-y^6*z^5+x^4*y^3+z^1-2^0"},
      {"(x+y)²⁰ × z", "(x+y)^20 * z"},
      {"π·x² ÷ 3", "pi*x^2/3"},
      {"x\u00A0+\u2009y\u202F−\u00A0z", "x + y - z"},
      {"−x²", "-x^2"},
      {"x² – 1 – y", "x^2 - 1 - y"},  // the en dash word processors make of " - "
      {"2²·x", "4*x"},
      {"2⁻¹·x + 10⁺²", "2^-1*x + 10^+2"},
      {"𝑥² + 𝑦² + 𝑧² − 𝑟² + 𝜋·𝑎·𝑥", "x^2 + y^2 + z^2 - r^2 + pi*a*x"},
      {"(𝑥²+𝑦²+𝑧²+𝑅²−𝑟²)² = 4·𝑅²·(𝑥²+𝑦²)", "(x^2+y^2+z^2+R^2-r^2)^2 = 4*R^2*(x^2+y^2)"},
  };
  ParseOptions o;
  o.parameters = {{"R", 1.0}, {"r", 0.4}, {"a", 2.0}};
  for (const auto& [typographic, ascii] : same) {
    SCOPED_TRACE(typographic);
    EXPECT_EQ(parsePolynomial(typographic, o), parsePolynomial(ascii, o));
  }
  // Columns count characters as written (a superscript run is one '^' and its exponent).
  const Rejection cases[] = {
      {"x⁴¹", 2, "degree 41 exceeds the limit 40"},
      {"(x²+y²)²¹ − 1", 8, "degree 42 exceeds the limit 40"},
      {"x²²²²²²²²²²", 2, "superscript exponent '²²²²²²²²²²' is too large"},
      {"2π", 2, "missing operator before 'π'"},
      {"x² y²", 4, "missing operator before 'y'"},
      {"²x", 1, "expected a number, a name or '('"},
      {"x − q", 5, "unknown name 'q'"},
      {"y + x⁻¹", 6, "exponent must be a non-negative integer (it is -1)"},
      {"𝑥𝑦 + 1", 2, "missing operator before '𝑦'"},
      {"𝑥 + 𝑞", 5, "unknown name 'q'"},
      {"x\u200B + 1", 2, "unexpected character '\u200B' (U+200B)"},
      {"x — 1", 3, "unexpected character '—' (U+2014)"},
      {"x + \xff", 5, "unexpected character '\\xFF'"},
      // A superscript run where an operand belongs is named as written, all of it (its '^'
      // token spans the run, three bytes a digit here).
      {"x^⁴²", 3, "expected a number, a name or '(' but found '⁴²'"},
  };
  for (const Rejection& r : cases) expectRejected(r);
  // Up to nine superscript digits are an exponent like any other (ten are refused above):
  // the same error as the ASCII spelling, at the same column.
  const std::pair<const char*, const char*> sameError[] = {{"x¹²³⁴⁵⁶⁷⁸⁹", "x^123456789"},
                                                           {"y + x⁹⁹⁹⁹⁹⁹⁹⁹⁹", "y + x^999999999"}};
  for (const auto& [typographic, ascii] : sameError) {
    std::string expected = "(accepted)", got = "(accepted)";
    try {
      parsePolynomial(ascii);
    } catch (const ParseError& e) {
      expected = e.what();
    }
    try {
      parsePolynomial(typographic);
    } catch (const ParseError& e) {
      got = e.what();
    }
    EXPECT_NE(expected, "(accepted)") << ascii;
    EXPECT_EQ(got, expected) << typographic;
  }
  // π is built in: no parameter may take its name; an italic letter names the plain one.
  ParseOptions clash;
  clash.parameters = {{"π", 3.0}};
  EXPECT_THROW(parsePolynomial("x", clash), ParameterError);
  clash.parameters = {{"𝑎", 3.0}};
  EXPECT_THROW(parsePolynomial("x", clash), ParameterError);
}

// A character the language has no use for is shown as written with its code point (U+0416
// is the Cyrillic capital Zhe, U+00E9 e acute, U+1F600 a grinning face: Unicode's charts),
// four hex digits at least; control characters (U+0001, U+007F DEL) and byte sequences that
// are not UTF-8 (RFC 3629: the overlong E0 80 AF for '/', the surrogate ED A0 80 for U+D800,
// F4 90 80 80 for U+110000, past the last code point U+10FFFF, the first three bytes of a
// four-byte sequence cut short by an 'x') as their bytes.
TEST(Parser, UnexpectedCharactersShowTheirCodePointOrTheirBytes) {
  const Rejection cases[] = {
      {"x \u0416 1", 3, "unexpected character '\u0416' (U+0416)"},
      {"x + \u00e9", 5, "unexpected character '\u00e9' (U+00E9)"},
      {"x \U0001F600", 3, "unexpected character '\U0001F600' (U+1F600)"},
      {"x\x01", 2, "unexpected character '\\x01'"},
      {"x\x7f + 1", 2, "unexpected character '\\x7F'"},
      {"x\xe0\x80\xaf", 2, "unexpected character '\\xE0\\x80\\xAF'"},
      {"x\xed\xa0\x80", 2, "unexpected character '\\xED\\xA0\\x80'"},
      {"x\xf4\x90\x80\x80", 2, "unexpected character '\\xF4\\x90\\x80\\x80'"},
      {"\xf0\x9d\x90x + 1", 1, "unexpected character '\\xF0\\x9D\\x90'"},
  };
  for (const Rejection& r : cases) expectRejected(r);
}

// ParseError::unknownName names an undefined name a parameter could give, so that tools can
// say how their users give one; not a glued product or an unknown function.
// Every mathematical italic letter, capital (U+1D434..U+1D44D) and small (U+1D44E..U+1D467,
// U+210E for the unassigned italic h), reads as its plain letter: as a coordinate or as a
// parameter's name (the capitals were refused: a pasted torus's R).
TEST(Parser, EveryItalicLetterIsItsPlainLetter) {
  auto utf8 = [](unsigned cp) {
    std::string out;
    out += static_cast<char>(0xF0 | (cp >> 18));
    out += static_cast<char>(0x80 | ((cp >> 12) & 0x3F));
    out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (cp & 0x3F));
    return out;
  };
  const std::string letters = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz";
  int checked = 0;
  for (size_t k = 0; k < letters.size(); ++k) {
    const std::string plain(1, letters[k]);
    const std::string italic = 0x1D434 + k == 0x1D455 ? "\u210E" : utf8(0x1D434 + k);
    ParseOptions o;
    const bool coordinate = plain == "x" || plain == "y" || plain == "z";
    if (!coordinate && plain != "e")  // (e is built in)
      o.parameters = {{plain, 2.0 + static_cast<double>(k)}};
    const std::string tail = coordinate ? " + 1" : "*x + 1";
    SCOPED_TRACE(plain);
    EXPECT_EQ(parsePolynomial(italic + tail, o), parsePolynomial(plain + tail, o));
    ++checked;
  }
  EXPECT_EQ(checked, 52);
}

TEST(Parser, UnknownNamesAreNamed) {
  auto unknownName = [](const char* text, const ParseOptions& options = {}) {
    try {
      parsePolynomial(text, options);
    } catch (const ParseError& e) {
      return e.unknownName();
    }
    return std::string("(accepted)");
  };
  EXPECT_EQ(unknownName("x + q"), "q");
  EXPECT_EQ(unknownName("x^2 + y^2 - radius^2"), "radius");
  ParseOptions withB;
  withB.parameters = {{"b", 1.0}};
  EXPECT_EQ(unknownName("a*x + b", withB), "a");
  EXPECT_EQ(unknownName("2*xy + 1"), "");
  EXPECT_EQ(unknownName("foo(2)*x"), "");
  EXPECT_EQ(unknownName("x^0.5"), "");
  // A coordinate in upper case is taken for a typo where no parameter is given at all.
  EXPECT_EQ(unknownName("X + Y"), "");
  ParseOptions withX;
  withX.parameters = {{"X", 1.0}};
  EXPECT_EQ(unknownName("X*x + Y", withX), "Y");
  EXPECT_EQ(unknownName("x + 1"), "(accepted)");
  EXPECT_EQ(unknownName("𝑥 − 𝑞"), "q");
}

// Leading zeros change neither the value nor whether a literal under- or overflows:
// 1e-330 is below half the smallest subnormal (2^-1075 ~ 2.5e-324), so it rounds to 0,
// however many zeros precede it; 1e309 is above DBL_MAX however written.
TEST(Parser, LeadingZerosDoNotTurnAnUnderflowIntoAnOverflow) {
  const std::string zeros(400, '0');
  EXPECT_EQ(parsePolynomial(zeros + "1e-330*x + 1"), Polynomial(1.0));
  EXPECT_EQ(parsePolynomial(zeros + "1.5e-300*x").coeff(1, 0, 0), 1.5e-300);
  EXPECT_EQ(parsePolynomial(zeros + "." + zeros + "1e-300*x + 1"), Polynomial(1.0));
  expectRejected({("x + " + zeros + "1e309").c_str(), 5, "is too large for double"});
}

// An exponent of any length: 10^-(10^19) is below the smallest subnormal, 10^(10^19) above
// the largest double, however many digits the exponent has (the lexer stops accumulating
// at 100000; a 64-bit accumulator wraps past 9.2e18, and 19 nines wrap to a negative
// number). The mantissa's leading zeros after the point move the literal down: 0.(400
// zeros)1e70 is 1e-331, which rounds to 0, not 1e70; 0.(400 zeros)1e700 is 1e299 and
// 0.(400 zeros)1e800 is 1e399, too large.
TEST(Parser, LongExponentsAndZerosAfterThePointKeepTheirSign) {
  for (int length : {19, 26, 40, 400}) {
    const std::string nines(length, '9');
    SCOPED_TRACE(length);
    EXPECT_EQ(parsePolynomial("1e-" + nines + "*x + 1"), Polynomial(1.0));
    expectRejected({("x + 1e" + nines).c_str(), 5, "is too large for double"});
    expectRejected({("x + 1e+" + nines).c_str(), 5, "is too large for double"});
  }
  const std::string zeros(400, '0');
  for (const std::string point : {"0.", "."}) {
    SCOPED_TRACE(point);
    EXPECT_EQ(parsePolynomial(point + zeros + "1e70*x + 1"), Polynomial(1.0));
    EXPECT_EQ(parsePolynomial(point + zeros + "1e700*x").coeff(1, 0, 0), 1e299);
    expectRejected({("x + " + point + zeros + "1e800").c_str(), 5, "is too large for double"});
  }
}

// Values near the largest double: their rounding-error bounds (tracked_value.h) overflow
// first (the power rule's bound is ~1000 times 2^1016, a sum's adds both sides'), and
// without a bound rounding junk cannot be told from a coefficient (sqrt(1.7e308)^2*x -
// 1.7e308*x is 2e292 x of junk), so they are refused, by what they are: until session 42
// the message called 2^1016 or exp(709) "not finite" and printed the finite value. Values
// a little lower are accepted as the same double arithmetic in C++ computes them (libm's
// pow and exp, as the parser's).
TEST(Parser, ValuesNearTheLargestDoubleAreNamedAsSuch) {
  const char* kTooClose = "comes so close to the largest double that its rounding-error bound";
  for (const char* text :
       {"2^1016", "10^306", "exp(709)", "exp(709)*1e-300*x", "1.5e308 - 1e308", "(1.7e308)^1",
        "2^1023*x", "1.5e308*x - 1e308*x", "sqrt(1.7e308)^2*x - 1.7e308*x + 2e292*z"}) {
    try {
      parsePolynomial(text);
      ADD_FAILURE() << text << " was accepted";
    } catch (const ParseError& e) {
      EXPECT_NE(std::string(e.what()).find(kTooClose), std::string::npos)
          << text << ": " << e.what();
    }
  }
  const Polynomial x = parsePolynomial("x");
  const struct {
    const char* text;
    Polynomial expected;
  } accepted[] = {
      {"2^1000", Polynomial(std::ldexp(1.0, 1000))},
      {"10^300", Polynomial(std::pow(10.0, 300.0))},
      {"exp(690)*x", std::exp(690.0) * x},
      {"1e305*x", 1e305 * x},
  };
  for (const auto& c : accepted) {
    Polynomial p;
    ASSERT_NO_THROW(p = parsePolynomial(c.text)) << c.text;
    EXPECT_EQ(p, c.expected) << c.text;
  }
  // log's slope 1/x overflows at a subnormal x, its bound (about 1 + |log x|) does not:
  // log(1e-320) was "so close to the largest double".
  for (const double tiny : {1e-320, 1e-310, 2.2250738585072009e-308}) {
    char text[64];
    std::snprintf(text, sizeof text, "log(%.17g)*x + ln(%.17g)", tiny, tiny);
    Polynomial p;
    ASSERT_NO_THROW(p = parsePolynomial(text)) << text;
    EXPECT_EQ(p, std::log(tiny) * x + Polynomial(std::log(tiny))) << text;
  }
  // Beyond the largest double they are not finite, as before.
  for (const char* text : {"2^1024", "1e308*10", "exp(710)"}) {
    try {
      parsePolynomial(text);
      ADD_FAILURE() << text << " was accepted";
    } catch (const ParseError& e) {
      EXPECT_NE(std::string(e.what()).find("not finite"), std::string::npos) << text;
    }
  }
}

// Powers of constants keep every coefficient of what they multiply: (x + 3^2)^n has the
// binomial coefficients C(n, k) 9^(n-k), here against their products in long double, and
// wider expansions keep all their terms. Until session 52 the power rule folded its error
// factors into the bound's magnitude (5.2 |c^e| for 3^2), products multiplied them, and
// (x + 3^2)^40 kept 19 of its 41 coefficients: the rest, sums of terms of one sign, were
// pruned as rounding junk (audit 1 of session 52, against sympy).
TEST(Parser, PowersOfConstantsKeepEveryCoefficient) {
  for (int n = 1; n <= 40; ++n) {
    const Polynomial p = parsePolynomial("(x + 3^2)^" + std::to_string(n));
    ASSERT_EQ(p.nonZeroCount(), n + 1) << n;
    long double binomial = 1;  // C(n, k)
    for (int k = 0; k <= n; ++k) {
      const long double expected = binomial * std::pow(9.0L, n - k);
      EXPECT_NEAR(p.coeff(k, 0, 0) / static_cast<double>(expected), 1.0, 1e-14) << n << " " << k;
      binomial = binomial * (n - k) / (k + 1);
    }
  }
  // Functions of constants alike (their argument's error went into the magnitude too:
  // (x + exp(3))^40 kept 23 coefficients, (x + tan(1.4))^40 14).
  const struct {
    const char* text;
    long double value;
  } functions[] = {{"exp(3)", std::exp(3.0L)},
                   {"tan(1.4)", std::tan(1.4L)},
                   {"sqrt(7)", std::sqrt(7.0L)},
                   {"log(20)", std::log(20.0L)}};
  for (const auto& f : functions) {
    const Polynomial p = parsePolynomial("(x + " + std::string(f.text) + ")^40");
    EXPECT_EQ(p.nonZeroCount(), 41) << f.text;
    EXPECT_NEAR(p.coeff(0, 0, 0) / static_cast<double>(std::pow(f.value, 40)), 1.0, 1e-13)
        << f.text;
  }
  EXPECT_EQ(parsePolynomial("(x + y + z + exp(2))^40").nonZeroCount(), 12341);
  // Wider expansions keep all their terms: (y(y+z)/3 - c - x)^n has one coefficient per
  // exponent triple (i, j, k) of x, y^2 and yz with i + j + k <= n, C(n + 3, 3) of them;
  // (x + y + z + c)^40 one per monomial of degree <= 40.
  EXPECT_EQ(parsePolynomial("(y/3*(y+z) - 3^2 - x)^20").nonZeroCount(), 1771);
  EXPECT_EQ(parsePolynomial("((y/0.966)*(y+z) - 9.^7 - x)^10").nonZeroCount(), 286);
  EXPECT_EQ(parsePolynomial("(x + y + z + 2^0.5)^40").nonZeroCount(), 12341);
  EXPECT_EQ(parsePolynomial("(x - 1.5^2)^24").nonZeroCount(), 25);
}

// A constant that cancelled (2 - 1, 1.0001 - 1, 1.3 - 1.1) keeps every coefficient of the
// powers it enters: its relative error enters each product once (d(ab) = da b + a db).
// Until session 52 the bound's magnitude multiplied through the products as the absolute
// expansion, 3^40 times the constant's own for (x + 2 - 1)^40, and the pruning rule took
// 13 of its 41 coefficients for junk; (x + (1.0001 - 1))^10 kept 4 of 11. References:
// C(n, k) c^(n-k) in long double, c the literals' exact difference.
TEST(Parser, CancelledConstantsKeepTheirPowersCoefficients) {
  const struct {
    const char* base;
    int n;
    long double c;
    double tolerance;  // the literals' rounding, amplified by the cancellation
  } cases[] = {{"x + 2 - 1", 40, 1.0L, 1e-14},
               {"x + (2 - 1)", 40, 1.0L, 1e-14},
               {"x + (1.0001 - 1)", 10, 1e-4L, 1e-10},
               {"x + (1.3 - 1.1)", 40, 0.2L, 1e-13},
               {"x + 1/(1.3 - 1.1)", 40, 5.0L, 1e-13}};
  for (const auto& c : cases) {
    const Polynomial p = parsePolynomial("(" + std::string(c.base) + ")^" + std::to_string(c.n));
    ASSERT_EQ(p.nonZeroCount(), c.n + 1) << c.base;
    long double binomial = 1;
    for (int k = 0; k <= c.n; ++k) {
      const long double expected = binomial * std::pow(c.c, c.n - k);
      EXPECT_NEAR(p.coeff(k, 0, 0) / static_cast<double>(expected), 1.0, c.tolerance)
          << c.base << " " << k;
      binomial = binomial * (c.n - k) / (k + 1);
    }
  }
  // A torus-like quartic written with such a constant, to the 10th power, keeps its
  // constant term 0.2^20 (pruned before), and rounding junk still vanishes.
  EXPECT_GT(parsePolynomial("((x^2+y^2+z^2+1.3-1.1)^2-4*(x^2+y^2))^10").coeff(0, 0, 0), 0.0);
  EXPECT_TRUE(parsePolynomial("(x + (2 - 1))^20 - (x + 1)^20").isZero());
  EXPECT_TRUE(parsePolynomial("(x + 0.1)^2 - x^2 - 0.2*x - 0.01").isZero());
}

// Terms of one sum keep their own error weights (session 52's review, against sympy): a
// first version of the fixes above put a power's, function's or divisor's error factor
// into the rounding count, which every term of a sum shares, and the other terms' real
// coefficients were pruned: the x terms below (exact 6.5255417158 x, 1e-6 x, 1e-8 x, 1e-12
// x, 1e-13 x), each known to 1e-4 or better, were dropped.
TEST(Parser, TermsOfASumKeepTheirOwnErrorBounds) {
  const struct {
    const char* text;
    double x;          // the exact coefficient of x (sympy, on the decimal literals)
    double tolerance;  // relative, the literals' rounding through the cancellation
  } cases[] = {
      {"x*(((2e9 + 2.8932) - 2e9) - tan(3e7))", 6.52554171584629405, 1e-6},
      {"x^2/(pi - 3.14159265) + (1.000001 - 1)*x", 1e-6, 1e-9},
      {"tan(1.5707963)*x^2 + (1.00000001 - 1)*x", 1e-8, 1e-7},
      {"x^2/(1.0001 - 1) + (1 - 0.999999999999)*x", 1e-12, 1e-3},
      {"2^1000*x^2 + (1 - 0.9999999999999)*x", 1e-13, 1e-2},
  };
  for (const auto& c : cases)
    EXPECT_NEAR(parsePolynomial(c.text).coeff(1, 0, 0) / c.x, 1.0, c.tolerance) << c.text;
}

TEST(Parser, FoldsWithoutCorrectDigitsAreRejectedNotZeroed) {
  // A function at a pole or a power whose rounding error exceeds its value is reported
  // at the call or the '^' instead of being pruned to 0 like rounding junk.
  const Rejection cases[] = {
      {"x - tan(pi/2)", 5, "tan(1.5707963267948966) is at a pole within rounding"},
      {"x*tan(pi/2)+y", 3, "at a pole within rounding"},
      {"tan(pi/2)*x^2+y^2+z^2-1", 1, "at a pole within rounding"},
      {"tan(-pi/2)*x", 1, "at a pole within rounding"},
      {"y + tan(3*pi/2)*x", 5, "at a pole within rounding"},
      {"1.0000000000000002^1e16*x", 19, "power too large for the base's accuracy"},
      {"y + (x-x+1.0000000000000002)^1e16*x", 29, "power too large for the base's accuracy"},
      {"sin(1e17)*x + y", 1, "sin(1e+17) has no correct digit"},
      // Arguments known to a radian or worse, or whose factors lost every digit, as the
      // same session's review found them (read as cos(0) = 1, sin(0) = 0 and exp(0) = 1,
      // exact cos(3.4822) = -0.94, sin(pi/2 + 1) = 0.54, exp(1) = 2.72): a function's bound
      // takes its slope's largest value within the argument's error, and products keep
      // their second-order term.
      {"x*cos(3e14*pi - (3e14*pi - 3.4822))", 3, "has no correct digit"},
      {"x*cos(pi + (1e17 + 1 - 1e17))", 3, "has no correct digit"},
      {"x*sin(pi/2 + (1e17 + 1 - 1e17))", 3, "has no correct digit"},
      {"x^2 + y^2 - exp((1e17 + 1 - 1e17)*(1e17 + 1 - 1e17))", 13, "has no correct digit"},
  };
  for (const Rejection& r : cases) expectRejected(r);
  // Near those limits the values are kept, and agree with references computed without the
  // parser: the libm tangent, and (1 + 2^-52)^1e15 = exp(1e15 log1p(2^-52)).
  EXPECT_EQ(parsePolynomial("tan(1.5707963)*x").coeff(1, 0, 0), std::tan(1.5707963));
  EXPECT_NEAR(parsePolynomial("1.0000000000000002^1e15*x").coeff(1, 0, 0),
              std::exp(1e15 * std::log1p(0x1p-52)), 1e-6);
  // Exact cancellations of functions at their zeros stay exact zeros (sin(k pi), cos at
  // odd multiples of pi/2, tan(k pi), log(1 + u)).
  for (const char* zero :
       {"sin(pi)*x", "cos(pi/2)*x", "x + cos(3*pi/2) - x", "sin(2*pi)*x + sin(-pi)", "tan(pi)*x",
        "tan(-2*pi)", "log(1.0000000000000002)*x", "ln(0.9999999999999999)*y"})
    EXPECT_TRUE(parsePolynomial(zero).isZero()) << zero;
  EXPECT_EQ(parsePolynomial("sin(pi)*x + y"), Polynomial::variable(1));
  EXPECT_TRUE(parsePolynomial("x - x").isZero());
  EXPECT_TRUE(parsePolynomial("(x+1)^2 - x^2 - 2*x - 1").isZero());
}

// Underflow: a product, quotient or power below 2^-1022 errs by an absolute amount that a
// later scaling amplifies; the bound tracks it (tracked_value.h), so a value it swallows
// is a ParseError, never a silent 0 or a coefficient of the wrong size (until session 43,
// x*1e-170*1e-170*1e300 parsed to the zero polynomial). References: MPFR on the decimal
// literals (320 bits; exp(-800) from mpfr_exp).
namespace underflow {

test::Mp dec(const char* s) {
  test::Mp r;
  mpfr_set_str(r.get(), s, 10, MPFR_RNDN);
  return r;
}

// The parse of `text` (whose x-coefficient is exactly `exact`, a non-zero normal double)
// is either refused as lost to underflow or within its own size of the exact value (no
// swallowed value); `mustParse` for the ones whose error stays below the value.
void expectHonest(const std::string& text, const test::Mp& exact, bool mustParse) {
  const double e = exact.toDouble();
  ASSERT_GE(std::abs(e), 0x1p-1022) << text;  // the premise: 0 would be wrong
  try {
    const double c = parsePolynomial(text).coeff(1, 0, 0);
    const double err = abs(test::Mp(c) - exact).toDouble();
    EXPECT_LT(err, 0.5 * std::abs(e)) << text << " -> " << c << ", exact " << e;
  } catch (const ParseError& error) {
    EXPECT_FALSE(mustParse) << text << ": " << error.what();
    const std::string& m = error.message();  // (or an overflow of a random chain)
    EXPECT_TRUE(m.find("lost to underflow") != std::string::npos ||
                m.find("not finite") != std::string::npos)
        << text << ": " << error.what();
  }
}

}  // namespace underflow

TEST(Parser, ValuesLostToUnderflowAreRejectedNotZeroed) {
  using underflow::dec;
  const Rejection cases[] = {
      {"x*1e-170*1e-170*1e300", 16, "a coefficient is lost to underflow"},
      {"1e-200^2*1e300*x", 9, "the value is lost to underflow"},
      {"exp(-800)*1e300*x", 10, "the value is lost to underflow"},
      {"2^-1075*2^100*x", 8, "the value is lost to underflow"},
      {"x*1e-160*1e-160*1e300 - 9.9998886718268303e-21*x", 23, "lost to underflow"},
      {"sqrt(1e-170*1e-170)*x", 1, "lost to underflow"},
      {"(x + 1e-200)^6*1e300", 15, "lost to underflow"},
      {"x/(1e-170*1e-170)", 3, "division by a value lost to underflow"},
  };
  for (const Rejection& r : cases) expectRejected(r);
  // The same with their exact coefficients; the wrong digits of 1e-160*1e-160 (a
  // subnormal, relative error 1.1e-5) are within the bound and kept.
  test::Mp e800;
  mpfr_exp(e800.get(), test::Mp(-800.0).get(), MPFR_RNDN);
  underflow::expectHonest("x*1e-170*1e-170*1e300", dec("1e-40"), false);
  underflow::expectHonest("1e-200^2*1e300*x", dec("1e-100"), false);
  underflow::expectHonest("exp(-800)*1e300*x", e800 * dec("1e300"), false);
  underflow::expectHonest("2^-1075*2^100*x", test::Mp(0x1p-975), false);
  underflow::expectHonest("x*1e-160*1e-160*1e300", dec("1e-20"), true);
  underflow::expectHonest("x*1e-323*1e300", dec("1e-23"), true);
  underflow::expectHonest("x*1e-160*1e-160*1e300 - 9.9998886718268303e-21*x",
                          dec("1e-20") - dec("9.9998886718268303e-21"), false);
  // Products of random powers of ten through the subnormal range and back.
  std::mt19937 rng(43);
  std::uniform_int_distribution<int> exponent(-330, 150), count(2, 5);
  for (int trial = 0; trial < 400; ++trial) {
    std::string text = "x";
    test::Mp exact(1.0);
    int total = 0;
    const int n = count(rng);
    for (int i = 0; i < n; ++i) {
      const int p = i + 1 < n ? exponent(rng) : std::clamp(-total - 20, -300, 300);
      total += p;
      text += (i % 2 ? "*3e" : "*1e") + std::to_string(p);
      exact *= dec(((i % 2 ? "3e" : "1e") + std::to_string(p)).c_str());
    }
    if (std::abs(exact.toDouble()) < 0x1p-1022 || std::abs(exact.toDouble()) > 1e300) continue;
    underflow::expectHonest(text, exact, false);
  }
  // At the floor of the format an underflow is the nearest double, as before.
  EXPECT_TRUE(parsePolynomial("x*1e-170*1e-170").isZero());
  EXPECT_TRUE(parsePolynomial("exp(-800)*x + 1e-200^2*y").isZero());
  EXPECT_EQ(parsePolynomial("2^-1074*x").coeff(1, 0, 0), 0x1p-1074);
}

// With rejectUnusedParameters a parameter the equation never reads is a ParameterError
// naming it; without, it is ignored (a format's fixed set, jsurf's a, b, c, d).
TEST(Parser, RejectsUnusedParametersOnlyWhenAsked) {
  ParseOptions o;
  o.parameters = {{"a", 2.0}, {"b", 3.0}, {"c", 5.0}};
  const Polynomial f = parsePolynomial("a*x + b*y", o);
  EXPECT_EQ(f, parsePolynomial("2*x + 3*y"));
  o.rejectUnusedParameters = true;
  try {
    parsePolynomial("a*x + b*y", o);
    ADD_FAILURE() << "unused parameter c accepted";
  } catch (const ParameterError& e) {
    EXPECT_EQ(e.name(), "c");
    EXPECT_NE(e.message().find("not used by the equation"), std::string::npos) << e.message();
  }
  // Read anywhere counts as used: inside a folded function, multiplied by zero, only on
  // the right-hand side.
  EXPECT_EQ(parsePolynomial("a*x + 0*b = -sqrt(c)", o), parsePolynomial("2*x + sqrt(5)"));
  // A malformed equation is reported as such first.
  EXPECT_THROW(parsePolynomial("a*x + ", o), ParseError);
}

TEST(Parser, RejectsBadParametersAndHonoursTheDegreeOption) {
  // A bad parameter is a ParameterError naming it (not a ParseError at a column of the
  // equation), whether or not the equation uses it.
  struct BadParameter {
    const char* name;
    double value;
    const char* equation;
    const char* message;
  };
  const BadParameter bad[] = {
      {"a", std::nan(""), "z + a", "is not finite"},
      {"b", INFINITY, "z*b", "is not finite"},
      {"b", -INFINITY, "z", "is not finite"},
      {"x", 2.0, "c*x", "clashes with the built-in name 'x'"},
      {"z", 2.0, "x + y", "clashes"},
      {"pi", 3.0, "x", "clashes"},
      {"e", 3.0, "e*x", "clashes"},
      {"sqrt", 3.0, "x", "clashes"},
      {"ln", 3.0, "x", "clashes"},
      {"2b", 1.0, "x", "is not a name an equation can use"},
      {"a ", 1.0, "a*x", "is not a name an equation can use"},
      {" a", 1.0, "a*x", "is not a name an equation can use"},
      {"", 1.0, "x", "is not a name an equation can use"},
      {"a-b", 1.0, "x", "is not a name an equation can use"},
      {"a.b", 1.0, "x", "is not a name an equation can use"},
      {"\xc3\xa9", 1.0, "x", "is not a name an equation can use"},
  };
  for (const BadParameter& b : bad) {
    ParseOptions o;
    o.parameters = {{"c", 1.0}, {b.name, b.value}};
    try {
      parsePolynomial(b.equation, o);
      ADD_FAILURE() << "accepted parameter " << b.name;
    } catch (const ParameterError& e) {
      EXPECT_EQ(e.name(), b.name);
      EXPECT_NE(e.message().find(b.message), std::string::npos) << e.message();
      EXPECT_EQ(std::string(e.what()), "parameter '" + std::string(b.name) + "': " + e.message());
    } catch (const ParseError& e) {
      ADD_FAILURE() << b.name << " reported in the equation: " << e.what();
    }
  }
  ParseOptions o;
  o.parameters = {{"a", 0.5}, {"c", 1.0}, {"X", 2.0}, {"pi2", 3.0}, {"_k1", 4.0}};
  expectRejected({"z + d", 5, "unknown name 'd' (parameters: X _k1 a c pi2)"}, o);
  EXPECT_EQ(parsePolynomial("c*x + X*pi2*y + _k1*z", o), parsePolynomial("x + 6*y + 4*z"));
  ParseOptions low;
  low.maxDegree = 4;
  expectRejected({"x^5", 2, "degree 5 exceeds the limit 4"}, low);
  expectRejected({"x^2*y^2*z", 8, "degree 5 exceeds the limit 4"}, low);
  EXPECT_EQ(parsePolynomial("x^2*y^2", low).degree(), 4);
  // Limit 0 (and anything below, clamped to 0): a bare variable is already degree 1.
  for (int limit : {0, -3}) {
    ParseOptions constantOnly;
    constantOnly.maxDegree = limit;
    expectRejected({"2 + y", 5, "degree 1 exceeds the limit 0"}, constantOnly);
    EXPECT_EQ(parsePolynomial("2*pi - 1", constantOnly).degree(), 0);
  }
}

TEST(Parser, DeepNestingIsAnErrorNotACrash) {
  const std::string deep = std::string(100000, '(') + "x" + std::string(100000, ')');
  EXPECT_THROW(parsePolynomial(deep), ParseError);
  EXPECT_THROW(parsePolynomial(std::string(100000, '-') + "x"), ParseError);
  const std::string fine = std::string(200, '(') + "x" + std::string(200, ')');
  EXPECT_EQ(parsePolynomial(fine), Polynomial::variable(0));
  // Long inputs are linear: a sum of 20000 terms.
  std::string sum = "0";
  for (int i = 0; i < 20000; ++i) sum += "+x";
  EXPECT_EQ(parsePolynomial(sum).coeff(1, 0, 0), 20000.0);
}

// Every ParseError is also an algray::Error (the type callers and the Embree boundary
// catch) and no input crashes or hangs: a sweep over all one- and two-character inputs.
TEST(Parser, NeverCrashesOnShortInputs) {
  const std::string alphabet = "xyz0123456789.e+-*/^()= ,a#";
  int accepted = 0, rejected = 0;
  for (char a : alphabet)
    for (char b : alphabet)
      for (char c : alphabet) {
        const std::string t{a, b, c};
        try {
          const Polynomial p = parsePolynomial(t);
          EXPECT_TRUE(p.isFinite());
          ++accepted;
        } catch (const ParseError& e) {
          EXPECT_GE(e.column(), 1) << t;
          EXPECT_LE(e.column(), 4) << t;
          ++rejected;
        }
      }
  EXPECT_GT(accepted, 100);
  EXPECT_GT(rejected, 100);
}

// Every string of three items from a set of typographic forms, ASCII and broken UTF-8
// sequences parses as its ASCII spelling does (the same polynomial, or an error for both),
// and an error's column lies within the text's characters (or just past them). The ASCII
// spelling is made here independently of the lexer: a run of superscript digits (after a
// superscript sign) becomes '^', the sign and the digits (and a space), the other forms their
// symbols.
TEST(Parser, TypographicFormsAsTheirAsciiSpelling) {
  const std::vector<std::string> items = {"x",    "2",        "²",    "¹",        "⁰", "⁴", "−",
                                          "·",    "×",        "÷",    "π",        "(", ")", "^",
                                          "\xc2", "\xe2\x81", "\xe2", "\xc2\xa0", "⁻", "⁺", "𝑥"};
  const std::vector<std::pair<std::string, std::string>> ascii = {
      {"−", "-"}, {"·", "*"}, {"×", "*"}, {"÷", "/"}, {"π", "pi"}, {"\xc2\xa0", " "}, {"𝑥", " x "}};
  const std::vector<std::pair<std::string, char>> superscripts = {
      {"²", '2'}, {"¹", '1'}, {"⁰", '0'}, {"⁴", '4'}};
  const std::vector<std::pair<std::string, char>> signs = {{"⁻", '-'}, {"⁺", '+'}};
  // The ASCII spelling, or nullopt where the text holds a byte that has none.
  auto spell = [&](const std::string& t) -> std::optional<std::string> {
    std::string out;
    bool inRun = false;
    for (size_t i = 0; i < t.size();) {
      bool matched = false;
      for (const auto& [form, digit] : superscripts)
        if (t.compare(i, form.size(), form) == 0) {
          if (!inRun) out += '^';
          out += digit;
          inRun = matched = true;
          i += form.size();
          break;
        }
      if (matched) continue;
      if (inRun) out += ' ';  // the run ends: "x²2" is x^2 2, not x^22
      inRun = false;
      // A superscript sign before a superscript digit opens a run: "x⁻²" is x^-2.
      for (const auto& [sign, symbol] : signs)
        for (const auto& [form, digit] : superscripts)
          if (!matched && t.compare(i, sign.size(), sign) == 0 &&
              t.compare(i + sign.size(), form.size(), form) == 0) {
            out += std::string("^") + symbol;
            inRun = matched = true;
            i += sign.size();
          }
      if (matched) continue;
      for (const auto& [form, symbol] : ascii)
        if (t.compare(i, form.size(), form) == 0) {
          out += symbol;
          matched = true;
          i += form.size();
          break;
        }
      if (matched) continue;
      if (static_cast<unsigned char>(t[i]) >= 0x80) return std::nullopt;
      out += t[i++];
    }
    return out;
  };
  int same = 0, bothRejected = 0;
  for (const std::string& a : items)
    for (const std::string& b : items)
      for (const std::string& c : items) {
        const std::string t = a + b + c;
        SCOPED_TRACE(t);
        std::optional<Polynomial> got;
        try {
          got = parsePolynomial(t);
          EXPECT_TRUE(got->isFinite());
        } catch (const ParseError& e) {
          EXPECT_GE(e.column(), 1);
          const auto characters = std::count_if(t.begin(), t.end(), [](char ch) {
            return (static_cast<unsigned char>(ch) & 0xC0) != 0x80;  // not a continuation byte
          });
          EXPECT_LE(e.column(), characters + 1);
        }
        const std::optional<std::string> spelled = spell(t);
        if (!spelled) {
          EXPECT_FALSE(got.has_value());
          continue;
        }
        std::optional<Polynomial> want;
        try {
          want = parsePolynomial(*spelled);
        } catch (const ParseError&) {
        }
        ASSERT_EQ(got.has_value(), want.has_value()) << *spelled;
        if (got) {
          EXPECT_EQ(*got, *want) << *spelled;
          ++same;
        } else {
          ++bothRejected;
        }
      }
  EXPECT_GT(same, 100);
  EXPECT_GT(bothRejected, 1000);
}

// Random token soup: every input is either accepted, with an expansion that agrees with
// the direct evaluation, or rejected with a column inside the text (or just past it).
TEST(Parser, RandomTokenSequences) {
  const char* tokens[] = {"x", "y",       "z",    "2", "0.5", "3",  "1e-3",  "pi",
                          "e", "sqrt(2)", "+",    "-", "*",   "/",  "^",     "(",
                          ")", "=",       "sin(", " ", "^2",  "^3", "(x+1)", "7/3"};
  std::mt19937_64 rng(2024);
  std::uniform_int_distribution<int> pick(0, std::size(tokens) - 1), length(1, 25);
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  int accepted = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    std::string text;
    for (int n = length(rng); n > 0; --n) text += tokens[pick(rng)];
    Polynomial f;
    try {
      f = parsePolynomial(text);
    } catch (const ParseError& e) {
      ASSERT_GE(e.column(), 1) << text;
      ASSERT_LE(e.column(), static_cast<int>(text.size()) + 1) << text;
      continue;
    }
    ++accepted;
    ASSERT_TRUE(f.isFinite()) << text;
    DirectEvaluator direct(text);
    const glm::dvec3 p(u(rng), u(rng), u(rng));
    const long double ref = direct(p.x, p.y, p.z);
    const auto ev = f.evaluateWithBound(p);
    ASSERT_FALSE(std::isnan(static_cast<double>(ref))) << text;
    EXPECT_LE(std::abs(static_cast<double>(ref - ev.value)),
              1e-12 * ev.magnitude + 4 * ev.valueError + 1e-300)
        << text;
  }
  EXPECT_GT(accepted, 300);
}

}  // namespace
}  // namespace algray
