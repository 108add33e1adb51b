#pragma once
// Equation parser: the notation people write and SURFER/jsurf files use, expanded to a
// Polynomial exactly as double arithmetic allows.
//   x^2 + y ^2 + z^2 - 1          (whitespace anywhere)
//   (x^2+y^2+z^2+R^2-r^2)^2 = 4*R^2*(x^2+y^2)   with parameters R, r from the caller
//   .5*x*y*z - 24/7 + sqrt(2)*pi  (functions of constants only are folded to numbers)
#include "algray/polynomial.h"

#include <map>
#include <string>
#include <string_view>

namespace algray {

// A rejected equation: the 1-based column of the offending character and a message.
class ParseError : public Error {
 public:
  ParseError(int column, const std::string& message);
  int column() const { return column_; }
  const std::string& message() const { return message_; }  // without the location

 private:
  int column_;
  std::string message_;
};

struct ParseOptions {
  std::map<std::string, double, std::less<>> parameters;  // named constants: a, b, ...
  int maxDegree = kMaxDegree;
};

// Parses "lhs = rhs" (meaning lhs - rhs) or a single expression. Throws ParseError.
Polynomial parsePolynomial(std::string_view text, const ParseOptions& options = {});

}  // namespace algray
