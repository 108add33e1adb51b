// Recursive-descent parser of the equation language (include/algray/parser.h). It
// evaluates while it parses: every subexpression becomes a TrackedValue (a constant or
// a polynomial with its rounding-error bound, see tracked_value.h), so the degree of an
// operand is known before a product or power is expanded and can be refused up front.
//
// Grammar (precedence low to high; '^' is right-associative and binds tighter than a
// unary sign, so -x^2 = -(x^2) and 2^-1 = 0.5):
//   equation := expr [ '=' expr ] END
//   expr     := term { ('+' | '-') term }
//   term     := unary { ('*' | '/') unary }
//   unary    := ('+' | '-') unary | power
//   power    := primary [ ('^' | '**') unary ]
//   primary  := NUMBER | NAME | FUNCTION '(' expr ')' | '(' expr ')'
#include "algray/parser.h"

#include "equation_lexer.h"
#include "tracked_value.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <set>

namespace algray {

ParseError::ParseError(int column, const std::string& message, const std::string& unknownName)
    : Error("column " + std::to_string(column) + ": " + message),
      column_(column),
      message_(message),
      unknownName_(unknownName) {}

ParseError::ParseError(int column, const std::string& before, int relatedColumn,
                       const std::string& after)
    : ParseError(column, before + "column " + std::to_string(relatedColumn) + after) {
  relatedColumn_ = relatedColumn;
  before_ = before;
  after_ = after;
}

std::string ParseError::messageWith(std::string_view place) const {
  return relatedColumn_ > 0 ? before_ + std::string(place) + after_ : message_;
}

ParseError ParseError::withHint(const std::string& more) const {
  ParseError e = relatedColumn_ > 0 ? ParseError(column_, before_, relatedColumn_, after_ + more)
                                    : ParseError(column_, message_ + more);
  e.unknownName_ = unknownName_;
  return e;
}

ParameterError::ParameterError(const std::string& name, const std::string& message)
    : Error("parameter '" + name + "': " + message), name_(name), message_(message) {}

namespace {

using detail::Token;
using detail::TokenKind;
using detail::TrackedValue;

std::string formatNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

class Parser {
 public:
  Parser(std::string_view text, const ParseOptions& options)
      : text_(text),
        options_(options),
        maxDegree_(std::clamp(options.maxDegree, 0, kMaxDegree)),
        tokens_(detail::tokenize(text)) {}

  Polynomial parseEquation() {
    if (peek().kind == TokenKind::End) throw ParseError(1, "empty equation");
    if (peek().kind == TokenKind::Equals) fail(peek(), "missing left-hand side before '='");
    TrackedValue value = parseExpr();
    if (peek().kind == TokenKind::Equals) {
      const Token equals = next();
      if (peek().kind == TokenKind::End) fail(equals, "missing right-hand side after '='");
      TrackedValue rhs = parseExpr();
      if (peek().kind == TokenKind::Equals) fail(peek(), "only one '=' is allowed in an equation");
      value = detail::add(value, rhs, /*subtract=*/true);
      checkFinite(value, equals);
    }
    const Token& t = peek();
    if (t.kind == TokenKind::RightParen) fail(t, "unbalanced parenthesis: ')' has no matching '('");
    if (t.kind != TokenKind::End) missingOperator(t);
    return value.toPolynomial();
  }

  // After parseEquation: a parameter the equation never read (ParseOptions::
  // rejectUnusedParameters).
  void checkAllParametersUsed() const {
    for (const auto& [name, value] : options_.parameters)
      if (!used_.contains(name))
        throw ParameterError(name, "is not used by the equation (a typo, or the wrong equation?)");
  }

 private:
  const Token& peek() const { return tokens_[pos_]; }
  const Token& next() { return tokens_[pos_++]; }
  int column(const Token& t) const { return detail::columnOf(text_, t.offset); }
  std::string_view spelling(const Token& t) const {
    return t.name.empty() ? text_.substr(t.offset, t.length) : t.name;
  }

  [[noreturn]] void fail(const Token& t, const std::string& message) const {
    throw ParseError(column(t), message);
  }
  [[noreturn]] void missingOperator(const Token& t) const {
    fail(t,
         "missing operator before " + detail::describe(text_, t) + " (write a product with '*')");
  }

  // The end of the message for a finite value whose rounding-error bound overflowed.
  static constexpr const char* kBoundOverflows =
      " comes so close to the largest double that its rounding-error bound overflows (scale the "
      "equation down)";

  void checkFinite(const TrackedValue& v, const Token& at) const {
    checkUnderflow(v, at);
    if (v.isFinite()) return;
    // A finite value whose rounding-error bound overflowed (within ~1000x of the largest
    // double): without a bound junk cannot be told from a coefficient, sqrt(1.7e308)^2 -
    // 1.7e308 from 2e292, so it is refused, but as what it is (it was "not finite").
    if (v.valuesFinite())
      fail(at, std::string(v.hasVariables ? "a coefficient" : "the value") + kBoundOverflows);
    if (v.hasVariables)
      fail(at, "coefficient overflow: the expansion is not finite in double precision");
    fail(at, "the value is not finite (" + formatNumber(v.value) + ")");
  }

  // The underflow rule (tracked_value.h): a value that underflowed, then was scaled up
  // beyond the smallest normal double, has lost its digits: refused where that happens.
  void checkUnderflow(const TrackedValue& v, const Token& at) const {
    const double loss = detail::underflowLoss(v);
    if (loss == 0.0) return;
    fail(at, std::string(v.hasVariables ? "a coefficient" : "the value") +
                 " is lost to underflow: a product, quotient or literal below the smallest normal "
                 "double (2.2e-308) was rounded, and here its error grows to " +
                 (std::isfinite(loss) ? "up to " + formatNumber(loss) : std::string("no bound")) +
                 ", beyond the value (scale the equation's constants)");
  }

  // A power of constants whose bound swallowed its non-zero value (tracked_value.h, fold
  // rule): reported rather than pruned to a silent 0.
  void checkFold(detail::Fold fold, const TrackedValue& base, const TrackedValue& exponent,
                 const Token& caret) const {
    if (fold != detail::Fold::undetermined) return;
    fail(caret, "power too large for the base's accuracy: " + formatNumber(base.value) + "^" +
                    formatNumber(exponent.value) +
                    " has no correct digit (the rounding error of its operands is amplified beyond "
                    "its value)");
  }

  void checkDegree(long long degree, const Token& at) const {
    if (degree > maxDegree_)
      fail(at,
           "degree " + std::to_string(degree) + " exceeds the limit " + std::to_string(maxDegree_));
  }

  TrackedValue parseExpr() {
    TrackedValue value = parseTerm();
    // Finiteness is checked once per chain (a scan of every coefficient); an overflow is
    // reported at the last '+' or '-' of the chain.
    const Token* lastOp = nullptr;
    while (peek().kind == TokenKind::Plus || peek().kind == TokenKind::Minus) {
      lastOp = &next();
      TrackedValue rhs = parseTerm();
      detail::accumulate(value, rhs, lastOp->kind == TokenKind::Minus);
    }
    if (lastOp) {
      checkFinite(value, *lastOp);
      detail::prune(value);
    }
    return value;
  }

  TrackedValue parseTerm() {
    TrackedValue value = parseUnary();
    for (;;) {
      const Token& t = peek();
      if (t.kind == TokenKind::Number || t.kind == TokenKind::Name ||
          t.kind == TokenKind::LeftParen)
        missingOperator(t);
      if (t.kind != TokenKind::Star && t.kind != TokenKind::Slash) return value;
      const Token op = next();
      const Token operandStart = peek();
      TrackedValue rhs = parseUnary();
      if (op.kind == TokenKind::Star) {
        if (value.hasVariables && rhs.hasVariables)
          checkDegree(static_cast<long long>(value.degree()) + rhs.degree(), op);
        value = detail::multiply(value, rhs);
      } else {
        if (rhs.hasVariables)
          fail(operandStart, "division by an expression in x, y, z is not a polynomial");
        if (rhs.underflow != 0.0 && 4.0 * rhs.underflow >= std::abs(rhs.value))
          fail(operandStart,
               "division by a value lost to underflow (below the smallest normal "
               "double, scale the equation's constants)");
        if (rhs.value == 0.0)
          fail(operandStart,
               rhs.magnitude == 0.0
                   ? "division by zero"
                   : "division by zero (the divisor cancels to zero within rounding)");
        value = detail::divide(value, rhs);
      }
      checkFinite(value, op);
    }
  }

  TrackedValue parseUnary() {
    // Every recursion (parentheses, signs, exponents) passes here: bound the depth so
    // that "((((...x" of any length is an error, not a stack overflow.
    struct DepthGuard {
      int& depth;
      explicit DepthGuard(int& d) : depth(++d) {}
      ~DepthGuard() { --depth; }
    } guard(depth_);
    if (depth_ > kMaxNesting)
      fail(peek(), "the expression is nested too deeply (more than " + std::to_string(kMaxNesting) +
                       " levels)");
    if (peek().kind == TokenKind::Minus) {
      next();
      return detail::negate(parseUnary());
    }
    if (peek().kind == TokenKind::Plus) {
      next();
      return parseUnary();
    }
    return parsePower();
  }

  TrackedValue parsePower() {
    TrackedValue base = parsePrimary();
    if (peek().kind != TokenKind::Caret) return base;
    const Token caret = next();
    const Token exponentStart = peek();
    TrackedValue exponent = parseUnary();
    if (exponent.hasVariables)
      fail(exponentStart, "exponent must be a constant (it contains x, y or z)");
    const double e = exponent.value;
    TrackedValue result;
    if (!base.hasVariables) {
      const detail::Fold fold = detail::constantPower(base, exponent, result);
      if (std::isnan(result.value) && std::isfinite(base.value) && std::isfinite(e))
        fail(caret, "power of a negative number to a non-integer exponent is not real");
      if (std::isinf(result.value) && base.value == 0.0)
        fail(caret, "division by zero (zero to a negative power)");
      checkFold(fold, base, exponent, caret);
    } else {
      if (!(e >= 0.0) || e != std::floor(e))
        fail(exponentStart, "exponent must be a non-negative integer (it is " + formatNumber(e) +
                                ") when the base contains x, y or z");
      const int degree = base.degree();
      if (degree <= 0) {
        // x - x + 2 and the like: a polynomial that reduced to a constant.
        const TrackedValue constantBase = base.asConstant();
        checkFold(detail::constantPower(constantBase, exponent, result), constantBase, exponent,
                  caret);
        result = detail::promoted(result);
      } else {
        if (e * degree > maxDegree_)
          fail(caret, e * degree < 1e6
                          ? "degree " + std::to_string(static_cast<long long>(e) * degree) +
                                " exceeds the limit " + std::to_string(maxDegree_)
                          : "exponent " + formatNumber(e) + " exceeds the degree limit " +
                                std::to_string(maxDegree_));
        result = detail::integerPower(base, static_cast<int>(e));
      }
    }
    checkFinite(result, caret);
    return result;
  }

  TrackedValue parsePrimary() {
    const Token t = next();
    switch (t.kind) {
      case TokenKind::Number: {
        if (!(std::abs(t.number) < 0x1p-1022)) return TrackedValue::constant(t.number);
        // Below the normal range: whether the digits are non-zero (1e-400 rounds to 0 but
        // is no exact 0).
        const std::string_view digits = spelling(t).substr(0, spelling(t).find_first_of("eE"));
        return TrackedValue::literal(t.number,
                                     digits.find_first_of("123456789") != std::string_view::npos);
      }
      case TokenKind::Name:
        return parseName(t);
      case TokenKind::LeftParen: {
        if (peek().kind == TokenKind::RightParen) fail(peek(), "empty parentheses");
        TrackedValue inner = parseExpr();
        closeParenthesis(t);
        return inner;
      }
      case TokenKind::End: {
        const Token& previous = tokens_[pos_ - 2 >= 0 ? pos_ - 2 : 0];
        fail(t, "the equation ends after " + detail::describe(text_, previous) +
                    " where an operand is expected");
      }
      case TokenKind::RightParen:
        if (pos_ >= 2 && tokens_[pos_ - 2].kind == TokenKind::LeftParen)
          fail(t, "empty parentheses");
        [[fallthrough]];
      default:
        if (t.kind == TokenKind::Equals && pos_ >= 2 &&
            tokens_[pos_ - 2].kind == TokenKind::Equals &&
            tokens_[pos_ - 2].offset + tokens_[pos_ - 2].length == t.offset)
          fail(t, "'==' is written '=' here (one '=' between the two sides)");
        fail(t, "expected a number, a name or '(' but found " + detail::describe(text_, t));
    }
  }

  void closeParenthesis(const Token& open) {
    const Token& t = peek();
    if (t.kind == TokenKind::RightParen) {
      next();
      return;
    }
    if (t.kind == TokenKind::End) fail(open, "unbalanced parenthesis: '(' is never closed");
    if (t.kind == TokenKind::Number || t.kind == TokenKind::Name || t.kind == TokenKind::LeftParen)
      missingOperator(t);
    throw ParseError(column(t), "expected ')' to close '(' at ", column(open),
                     " but found " + detail::describe(text_, t));
  }

  TrackedValue parseName(const Token& t) {
    const std::string_view name = spelling(t);
    // Parameters are checked up front (checkParameters): none shadows a built-in.
    const auto parameter = options_.parameters.find(name);
    if (name == "x" || name == "y" || name == "z") {
      // A bare variable is the one place the degree grows without a product or a power:
      // with maxDegree 0 it is already over the limit.
      checkDegree(1, t);
      return TrackedValue::variable(name[0] - 'x');
    }
    if (name == "pi") return TrackedValue::constant(std::numbers::pi);
    if (name == "e") return TrackedValue::constant(std::numbers::e);
    if (detail::isFunctionName(name)) return parseFunction(t, name);
    if (parameter != options_.parameters.end()) {
      used_.insert(parameter->first);
      return TrackedValue::constant(parameter->second);
    }
    std::string message = "unknown name '" + std::string(name) + "'";
    if (peek().kind == TokenKind::LeftParen) {
      fail(t, "unknown function '" + std::string(name) +
                  "' (known: sqrt, sin, cos, tan, exp, log, ln, abs)");
    } else if (name.find_first_not_of("xyz0123456789") == std::string_view::npos) {
      fail(t, message + " (write products with '*' and powers with '^', e.g. x*y or x^2)");
    } else if (options_.parameters.empty() &&
               name.find_first_not_of("XYZ") == std::string_view::npos) {
      fail(t, message + " (the coordinates are x, y, z, in lower case)");
    } else if (!options_.parameters.empty()) {
      message += " (parameters:";
      for (const auto& [key, value] : options_.parameters) message += " " + key;
      message += ")";
    }
    throw ParseError(column(t), message, std::string(name));
  }

  TrackedValue parseFunction(const Token& t, std::string_view name) {
    if (peek().kind != TokenKind::LeftParen)
      fail(t, "function '" + std::string(name) + "' needs an argument in parentheses");
    const Token open = next();
    if (peek().kind == TokenKind::RightParen) fail(peek(), "empty parentheses");
    TrackedValue argument = parseExpr();
    closeParenthesis(open);
    if (argument.hasVariables)
      fail(t, std::string(name) + "() of an expression in x, y, z is not a polynomial");
    TrackedValue result;
    const detail::Fold fold = detail::applyFunction(name, argument, result);
    if (std::isfinite(result.value) && !std::isfinite(result.magnitude))
      fail(t, "the value of " + std::string(name) + "(" + formatNumber(argument.value) + ")" +
                  kBoundOverflows);
    if (!std::isfinite(result.value)) {
      const std::string value = formatNumber(argument.value);
      if ((name == "sqrt" && argument.value < 0.0) ||
          ((name == "log" || name == "ln") && argument.value <= 0.0))
        fail(t, std::string(name) + "(" + value + ") is not a finite real number");
      fail(t, "the value of " + std::string(name) + "(" + value + ") is not finite");
    }
    checkUnderflow(result, t);
    if (fold == detail::Fold::undetermined) {
      // The fold rule (tracked_value.h): the value's bound is not rounding junk of a zero.
      const std::string call = std::string(name) + "(" + formatNumber(argument.value) + ")";
      if (name == "tan")
        fail(t, call + " is at a pole within rounding: its value " + formatNumber(result.value) +
                    " has no correct digit");
      fail(t, call + " has no correct digit: the argument's rounding error is too large for " +
                  std::string(name));
    }
    return result;
  }

  std::string_view text_;
  const ParseOptions& options_;
  int maxDegree_;
  std::vector<Token> tokens_;
  int pos_ = 0;
  int depth_ = 0;
  std::set<std::string, std::less<>> used_;  // the parameters read so far
  static constexpr int kMaxNesting =
      256;  // far beyond real equations; small stack frames even under ASan
};

// Whether an equation can refer to `name`: exactly one Name token of the lexer, spelled as
// written (an italic 𝑎 or π in the equation is the name a or pi).
bool isReferenceable(std::string_view name) {
  try {
    const std::vector<Token> tokens = detail::tokenize(name);
    return tokens.size() == 2 && tokens[0].kind == detail::TokenKind::Name &&
           tokens[0].offset == 0 && tokens[0].length == static_cast<int>(name.size()) &&
           tokens[0].name.empty();
  } catch (const ParseError&) {
    return false;
  }
}

// Before the equation is read, so that a bad parameter is reported as such (by name)
// whether or not the equation uses it, and never at a column of the equation. A name no
// equation could use ("2b", "a " from a command line's "a = 1") is a mistake, not an
// unused parameter: silently kept, it hid a typo behind "unknown name 'a'".
void checkParameters(const ParseOptions& options) {
  for (const auto& [name, value] : options.parameters) {
    if (!isReferenceable(name))
      throw ParameterError(
          name, "is not a name an equation can use (a letter or _, then letters, digits or _)");
    if (name == "x" || name == "y" || name == "z" || name == "pi" || name == "e" ||
        detail::isFunctionName(name))
      throw ParameterError(name, "clashes with the built-in name '" + name + "'");
    if (!std::isfinite(value))
      throw ParameterError(name, "is not finite (" + formatNumber(value) + ")");
  }
}

}  // namespace

Polynomial parsePolynomial(std::string_view text, const ParseOptions& options) {
  checkParameters(options);
  Parser parser(text, options);
  Polynomial f = parser.parseEquation();
  if (options.rejectUnusedParameters) parser.checkAllParametersUsed();
  return f;
}

}  // namespace algray
