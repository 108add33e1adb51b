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
  Name,    // x, y, z, pi, e, sqrt, a parameter: [A-Za-z_][A-Za-z0-9_]*; or a letter form
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

// Typographic forms are read as the symbols they stand for: mathematical italic letters
// as the letters (Token::name), U+2212 as '-', U+00B7,
// U+22C5, U+2219 and U+00D7 as '*', U+00F7 as '/', no-break and thin spaces as spaces,
// and superscript digits as '^' and an exponent (x² = x^2), with an optional superscript
// sign (2⁻¹ = 2^-1).
struct Token {
  TokenKind kind;
  int offset;  // byte offset of the first character
  int length;  // in bytes
  double number = 0.0;
  // A Name token's spelling where the text writes it otherwise: π is pi, and the
  // mathematical italic letters of pasted equations are the letters (𝑥 is x, 𝜋 is pi).
  std::string_view name = {};
};

// 1-based column of a byte offset (code points before it + 1).
int columnOf(std::string_view text, int offset);

// Display form of the token for messages: "'+'", "'sqrt'", "the end of the equation".
std::string describe(std::string_view text, const Token& token);

// Splits the text into tokens ending with one End token. Throws ParseError for a
// character that is not part of the language or a malformed or out-of-range number.
std::vector<Token> tokenize(std::string_view text);

}  // namespace algray::detail
