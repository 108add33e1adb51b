#pragma once
// Command-line text shared by algray-render and algray-query (the numbers and --param
// syntax in number_text.h, which the ray file reader uses too).
#include "number_text.h"

#include <algray/parser.h>

#include <CLI/CLI.hpp>

#include <optional>
#include <string>

namespace algray::cli {

// Integer options of the tools are decimal. CLI11 2.1 converts them with strtoll's base 0:
// "--width 010" rendered 8 pixels wide, "--height 0x10" 16, "--seed 0042" was seed 34 and
// "--width 08" "not in range". This transform, run before CLI11 converts, trims spaces (as
// around --param's values; " 2" was taken before), drops leading zeros and refuses
// anything but an optional sign and digits.
inline CLI::Validator decimal() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        text = trimmed(text);
        const size_t digits = !text.empty() && (text[0] == '-' || text[0] == '+') ? 1 : 0;
        if (digits == text.size() ||
            text.find_first_not_of("0123456789", digits) != std::string::npos)
          return "'" + text + "' is not a decimal integer";
        const size_t first = text.find_first_not_of('0', digits);
        text = text.substr(0, digits) + (first == std::string::npos ? "0" : text.substr(first));
        return "";
      },
      "DECIMAL");
}

// A --param VALUE that is no number may be a constant as an equation writes one:
// "phi=(1+sqrt(5))/2", "a=pi/4" (refused as "not a number" before session 53, though the
// equation itself reads them). Read by the equation parser, with its rounding rules; a
// value that uses x, y or z, or that the parser refuses, leaves `problem` saying why.
inline std::optional<double> constantExpression(const std::string& text, std::string& problem) {
  try {
    const Polynomial p = parsePolynomial(text);
    if (p.degree() > 0) {
      problem = "a parameter's value may not use x, y or z";
      return std::nullopt;
    }
    return p.coeff(0, 0, 0);
  } catch (const Error& e) {  // ParseError: "column N: message" of the value's text
    problem = e.what();
    return std::nullopt;
  }
}

}  // namespace algray::cli
