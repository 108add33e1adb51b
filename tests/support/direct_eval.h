#pragma once
// An independent reference for the parser tests: evaluates equation text (lhs - rhs) at
// one point in long double, straight from the characters, without expanding anything and
// without sharing code with plugin/core (no tokens, no polynomials). It accepts the
// well-formed inputs of the language only; on anything else it returns NaN.
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>
#include <numbers>
#include <string>

namespace algray::test {

class DirectEvaluator {
 public:
  DirectEvaluator(std::string text, std::map<std::string, double, std::less<>> parameters = {})
      : s_(std::move(text)), params_(std::move(parameters)) {}

  long double operator()(long double x, long double y, long double z) {
    x_ = x, y_ = y, z_ = z, i_ = 0, ok_ = true;
    long double v = expr();
    skip();
    if (i_ < s_.size() && s_[i_] == '=') {
      ++i_;
      v -= expr();
      skip();
    }
    return ok_ && i_ == s_.size() ? v : NAN;
  }

 private:
  void skip() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) ++i_;
  }
  bool eat(char c) {
    skip();
    if (i_ < s_.size() && s_[i_] == c) return ++i_, true;
    return false;
  }
  long double expr() {
    long double v = term();
    for (;;) {
      if (eat('+'))
        v += term();
      else if (eat('-'))
        v -= term();
      else
        return v;
    }
  }
  long double term() {
    long double v = unary();
    for (;;) {
      skip();
      if (i_ + 1 < s_.size() && s_[i_] == '*' && s_[i_ + 1] == '*') return v;
      if (eat('*'))
        v *= unary();
      else if (eat('/'))
        v /= unary();
      else
        return v;
    }
  }
  long double unary() {
    if (eat('-')) return -unary();
    if (eat('+')) return unary();
    return power();
  }
  long double power() {
    long double b = primary();
    skip();
    if (eat('^') || (i_ + 1 < s_.size() && s_[i_] == '*' && s_[i_ + 1] == '*' && (i_ += 2))) {
      const long double e = unary();
      // Integer exponents by repeated multiplication (exact in the reference sense).
      if (e == std::floor(e) && std::abs(e) <= 64) {
        long double r = 1;
        for (int k = 0; k < std::abs(static_cast<int>(e)); ++k) r *= b;
        return e < 0 ? 1 / r : r;
      }
      return std::pow(b, e);
    }
    return b;
  }
  long double primary() {
    skip();
    if (i_ >= s_.size()) return ok_ = false, 0;
    if (eat('(')) {
      const long double v = expr();
      if (!eat(')')) ok_ = false;
      return v;
    }
    const char c = s_[i_];
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') {
      char* end = nullptr;
      const long double v = std::strtold(s_.c_str() + i_, &end);
      i_ = static_cast<size_t>(end - s_.c_str());
      return v;
    }
    std::string name;
    while (i_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[i_])) || s_[i_] == '_'))
      name += s_[i_++];
    if (name == "x") return x_;
    if (name == "y") return y_;
    if (name == "z") return z_;
    if (name == "pi") return std::numbers::pi_v<long double>;
    if (name == "e") return std::numbers::e_v<long double>;
    if (auto it = params_.find(name); it != params_.end()) return it->second;
    if (eat('(')) {
      const long double a = expr();
      if (!eat(')')) ok_ = false;
      if (name == "sqrt") return std::sqrt(a);
      if (name == "sin") return std::sin(a);
      if (name == "cos") return std::cos(a);
      if (name == "tan") return std::tan(a);
      if (name == "exp") return std::exp(a);
      if (name == "log" || name == "ln") return std::log(a);
      if (name == "abs") return std::abs(a);
    }
    return ok_ = false, 0;
  }

  std::string s_;
  std::map<std::string, double, std::less<>> params_;
  size_t i_ = 0;
  bool ok_ = true;
  long double x_ = 0, y_ = 0, z_ = 0;
};

}  // namespace algray::test
