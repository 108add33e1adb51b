#pragma once
// Numbers and NAME=VALUE text as both tools read them, from options and from algray-query's
// ray file alike (no CLI11 here: ray_csv.cpp includes it).
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <string>

namespace algray::cli {

// Spaces around a name or a value are the shell's quoting, not part of it (strtod skipped
// leading ones only: "--param a= 1" was taken, "a=1 " refused).
inline std::string trimmed(const std::string& s) {
  const size_t first = s.find_first_not_of(" \t");
  return first == std::string::npos ? std::string()
                                    : s.substr(first, s.find_last_not_of(" \t") + 1 - first);
}

// A number as the tools read an option's value: strtod of the whole text, trimmed of spaces
// and tabs first (a quoted ray-file field " 1" was read and "1 " refused; strtod skips
// leading white space only, a newline or a form feed too, which stays refused here),
// within double's range. strtod, not std::stod: stod throws out_of_range for every ERANGE,
// so a subnormal value (--param a=1e-320, its own value) was "not a number", and so were an
// overflow and an underflow to 0, which are named here (1e-400 was silently 0 in
// algray-query). "inf" and "nan" are numbers to strtod; whether they are values is the
// tool's to say.
enum class NumberProblem { kNone, kNotANumber, kOverflows, kUnderflows };
struct Number {
  double value = 0;
  NumberProblem problem = NumberProblem::kNone;
};
inline Number readNumber(const std::string& given) {
  const std::string text = trimmed(given);
  char* end = nullptr;
  errno = 0;
  Number n;
  n.value = std::strtod(text.c_str(), &end);
  if (text.empty() || std::isspace(static_cast<unsigned char>(text.front())) ||
      end != text.c_str() + text.size())
    n.problem = NumberProblem::kNotANumber;
  else if (errno == ERANGE && std::isinf(n.value))
    n.problem = NumberProblem::kOverflows;
  else if (errno == ERANGE && n.value == 0.0)
    n.problem = NumberProblem::kUnderflows;
  return n;
}

// One --param NAME=VALUE of either tool: the name and the value's text trimmed (spaces
// around them are quoting), the value read as readNumber reads it. Each tool words the
// problems in its own messages.
struct Param {
  std::string name;  // empty: `given` is no NAME=VALUE (no '=', or nothing before it)
  std::string valueText;
  Number number;
};
inline Param readParam(const std::string& given) {
  Param p;
  const size_t eq = given.find('=');
  if (eq == std::string::npos) return p;
  p.name = trimmed(given.substr(0, eq));
  if (p.name.empty()) return p;
  p.valueText = trimmed(given.substr(eq + 1));
  p.number = readNumber(p.valueText);
  return p;
}

}  // namespace algray::cli
