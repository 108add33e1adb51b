#pragma once
// Tokens of the equation language (private to the parser, see parser.cpp for the grammar).
// Positions are byte offsets into the text; columnOf() turns them into the 1-based
// columns of ParseError, counting UTF-8 code points so that a column points at the
// character a reader sees.
#include <string>
#include <string_view>
#include <vector>

namespace algray::detail {

enum class TokenKind {
  Number,  // 2, .5, 1e-3, 2.5E+4 (decimal, read with correct rounding)
  Name,    // x, y, z, pi, e, sqrt, a parameter: [A-Za-z_][A-Za-z0-9_]*
  Plus,
  Minus,
  Star,
  Slash,
  Caret,  // ^ or **
  LeftParen,
  RightParen,
  Equals,
  End,  // one past the last token; its offset is the length of the text
};

struct Token {
  TokenKind kind;
  int offset;  // byte offset of the first character
  int length;  // in bytes
  double number = 0.0;
};

// 1-based column of a byte offset (code points before it + 1).
int columnOf(std::string_view text, int offset);

// Display form of the token for messages: "'+'", "'sqrt'", "the end of the equation".
std::string describe(std::string_view text, const Token& token);

// Splits the text into tokens ending with one End token. Throws ParseError for a
// character that is not part of the language or a malformed or out-of-range number.
std::vector<Token> tokenize(std::string_view text);

}  // namespace algray::detail
