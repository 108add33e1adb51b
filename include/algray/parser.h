#pragma once
// Equation parser: the notation people write and SURFER/jsurf files use, expanded to a
// Polynomial exactly as double arithmetic allows.
//   x^2 + y ^2 + z^2 - 1          (whitespace anywhere)
//   (x^2+y^2+z^2+R^2-r^2)^2 = 4*R^2*(x^2+y^2)   with parameters R, r from the caller
//   .5*x*y*z - 24/7 + sqrt(2)*pi  (functions of constants only are folded to numbers)
//
// Language: + - * / ^ (also **), parentheses, unary signs, an optional "lhs = rhs"
// (= lhs - rhs); literals 2 .5 1. 1e-3; names x y z, pi e, options.parameters, and
// sqrt sin cos tan exp log ln abs of constants; the typographic forms x² (superscript
// digits, 2⁻¹ with a sign), − (U+2212), · ⋅ ∙ ×, ÷, π, italic letters (𝑥) and no-break or
// thin spaces as the symbols they stand for (docs/equations.md). '^' is right-associative
// and binds tighter than a sign (-x^2 = -(x^2), 2^-1 = 0.5). A base containing x, y, z
// needs a non-negative integer constant exponent; divisors and function arguments must be
// free of x, y, z. The degree is checked before each product or power is expanded.
//
// Rounding junk is removed by a documented rule (plugin/core/tracked_value.h): every
// coefficient carries a running error bound gamma_k * M (Higham ch. 3), and after each
// operation a coefficient with |c| <= 2 gamma_k M is set to exactly 0. So
// (x+0.1)^2 - x^2 - 0.2*x - 0.01 is the zero polynomial while (x+1e-8)^3 - x^3 keeps its
// three small coefficients. A folded constant whose bound swallows a value that is not
// rounding junk of a zero (tan at a pole within rounding, a power whose rounding error
// exceeds its value) is a ParseError at the call or the '^', never a silent 0. So is a
// value lost to underflow: one rounded below 2^-1022 (absolutely, by up to 2^-1074) and
// then scaled up beyond the smallest normal double until that error swallows it
// (x*1e-170*1e-170*1e300, exact 1e-40 x, at its last '*'); the bound carries the absolute
// term, so a value it does not swallow is kept (x*1e-160*1e-160*1e300 is 9.99988867e-21 x).
#include "algray/polynomial.h"

#include <map>
#include <string>
#include <string_view>

namespace algray {

// A rejected equation: the 1-based column of the offending character and a message. A
// message may name a second place in the equation ("expected ')' to close '(' at column 3
// but found '='"): relatedColumn() is its column (0 if none), and messageWith() writes it
// the caller's way, so that a tool reporting the error at its file's line and column
// ("scene.json:2:36: ...") names the second place in the same terms, not the equation's.
class ParseError : public Error {
 public:
  ParseError(int column, const std::string& message, const std::string& unknownName = {});
  // The message is `before` + "column N" + `after`, N = relatedColumn.
  ParseError(int column, const std::string& before, int relatedColumn, const std::string& after);
  int column() const { return column_; }
  const std::string& message() const { return message_; }  // without the location
  // The name when the equation uses one that is neither built in nor a parameter (and
  // could be one: not a glued product such as "xy"), else empty: most often a parameter
  // the caller did not give, so a tool can say how its users give one.
  const std::string& unknownName() const { return unknownName_; }
  int relatedColumn() const { return relatedColumn_; }
  // message() with its "column N" of relatedColumn() written as `place` ("line 2, column
  // 30"); message() itself when there is no second place.
  std::string messageWith(std::string_view place) const;
  // A copy with `more` appended to the message (a caller's hint), the second place kept.
  ParseError withHint(const std::string& more) const;

 private:
  int column_;
  std::string message_;
  std::string unknownName_;
  int relatedColumn_ = 0;
  std::string before_, after_;  // message_ around "column N"
};

// A rejected entry of ParseOptions::parameters: a name that clashes with a built-in (x, y,
// z, pi, e, a function) or a value that is not finite. It is about the parameter, not a
// place in the equation, so it names the parameter instead of a column, and callers can
// report it where the parameter came from (an option, a JSON key, a file line). Every
// parameter is checked before the equation is read, used or not; with
// ParseOptions::rejectUnusedParameters one the equation never reads is refused after it.
class ParameterError : public Error {
 public:
  ParameterError(const std::string& name, const std::string& message);
  const std::string& name() const { return name_; }
  const std::string& message() const { return message_; }  // without the name; what() has both

 private:
  std::string name_;
  std::string message_;
};

struct ParseOptions {
  std::map<std::string, double, std::less<>> parameters;  // named constants: a, b, ...
  int maxDegree = kMaxDegree;                             // clamped to [0, kMaxDegree]
  // A parameter the equation does not use is a ParameterError ("is not used by the
  // equation") instead of being ignored: for a user's own parameters (a command line's
  // --param, a scene file's), where it is a mistake; not for a file format that always
  // defines the same set (jsurf's a, b, c, d).
  bool rejectUnusedParameters = false;
};

// Parses "lhs = rhs" (meaning lhs - rhs) or a single expression. Throws ParameterError
// for a bad parameter (what() is "parameter 'NAME': message"), else ParseError with the
// 1-based column (in code points) of the offending character; what() is
// "column N: message". Never crashes or hangs on any input (nesting depth is bounded).
Polynomial parsePolynomial(std::string_view text, const ParseOptions& options = {});

}  // namespace algray
