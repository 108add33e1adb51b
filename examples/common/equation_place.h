#pragma once
// Where the parser's column lies in an equation typed with line breaks (pasted from a paper
// or a file): the parser counts code points through the whole text, so "x^2+y^2\n+z^2-1 q"
// had its 'q' at "column 16" of "line 1", and algray-query's caret stood 16 columns into
// the two-line equation, under nothing.
#include <algray/parser.h>

#include <string>
#include <string_view>

namespace algray::cli {

struct EquationPlace {
  int line = 1;            // 1-based; lines end at "\n", "\r\n" or a lone "\r"
  int column = 1;          // 1-based, in code points of that line
  std::string_view text;   // that line, without its ending
  bool multiLine = false;  // whether the equation has a line break at all
};

inline EquationPlace equationPlace(std::string_view equation, int column) {
  EquationPlace at;
  at.multiLine = equation.find_first_of("\r\n") != std::string_view::npos;
  // An error at the very end ("the equation ends after '+'") of a text ending in line
  // breaks is at the end of its last line with a character, not on an empty line after it.
  size_t characters = 0;
  for (const char ch : equation) characters += (static_cast<unsigned char>(ch) & 0xC0) != 0x80;
  if (at.multiLine && column > static_cast<int>(characters)) {
    const size_t last = equation.find_last_not_of(" \t\r\n");
    equation = equation.substr(0, last == std::string_view::npos ? 0 : last + 1);
  }
  size_t lineStart = 0;
  int character = 1;  // the parser's column of equation[i]
  for (size_t i = 0; i < equation.size(); ++i) {
    const char ch = equation[i];
    if ((static_cast<unsigned char>(ch) & 0xC0) == 0x80) continue;  // inside a character
    if (character == column) break;
    ++character;
    ++at.column;
    const bool crlf = ch == '\r' && i + 1 < equation.size() && equation[i + 1] == '\n';
    if (ch == '\n' || (ch == '\r' && !crlf)) {
      ++at.line;
      at.column = 1;
      lineStart = i + 1;
    }
  }
  size_t lineEnd = lineStart;
  while (lineEnd < equation.size() && equation[lineEnd] != '\n' && equation[lineEnd] != '\r')
    ++lineEnd;
  at.text = equation.substr(lineStart, lineEnd - lineStart);
  return at;
}

// e's message with the second place it names (relatedColumn) in the equation's own lines
// where it has line breaks ("... at line 1, column 1 ..."), else as the parser wrote it.
inline std::string placedMessage(const ParseError& e, std::string_view equation) {
  if (e.relatedColumn() == 0) return e.message();
  const EquationPlace other = equationPlace(equation, e.relatedColumn());
  if (!other.multiLine) return e.message();
  return e.messageWith("line " + std::to_string(other.line) + ", column " +
                       std::to_string(other.column));
}

}  // namespace algray::cli
