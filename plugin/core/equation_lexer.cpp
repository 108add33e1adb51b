#include "equation_lexer.h"

#include "algray/parser.h"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <iterator>

namespace algray::detail {

namespace {

bool isDigit(char c) { return c >= '0' && c <= '9'; }
bool isNameStart(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; }
bool isNameChar(char c) { return isNameStart(c) || isDigit(c); }
bool isSpace(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v';
}
bool isContinuation(char c) { return (static_cast<unsigned char>(c) & 0xC0) == 0x80; }

// Length in bytes of the (possibly multi-byte UTF-8) character at text[i].
int charLength(std::string_view text, size_t i) {
  size_t j = i + 1;
  while (j < text.size() && isContinuation(text[j])) ++j;
  return static_cast<int>(j - i);
}

// Reads a decimal literal: digits [. digits] [(e|E) [+|-] digits], at least one digit in
// the mantissa. Values are rounded to nearest by std::from_chars (locale-independent).
Token readNumber(std::string_view text, size_t start) {
  size_t i = start;
  int mantissaDigits = 0;
  // Decimal exponent of the first non-zero digit relative to the point, to tell an
  // underflow (rounds to 0, accepted) from an overflow (rejected) below. Leading zeros
  // do not count: "000...01e-330" is as small as "1e-330".
  long firstNonZero = 0;
  bool seenNonZero = false, seenPoint = false;
  long digitsBeforePoint = 0, zerosAfterPoint = 0;
  for (; i < text.size(); ++i) {
    const char c = text[i];
    if (isDigit(c)) {
      ++mantissaDigits;
      if (!seenPoint && (seenNonZero || c != '0')) ++digitsBeforePoint;
      if (c != '0' && !seenNonZero) {
        seenNonZero = true;
        firstNonZero = seenPoint ? -(zerosAfterPoint + 1) : 0;
      } else if (c == '0' && seenPoint && !seenNonZero) {
        ++zerosAfterPoint;
      }
    } else if (c == '.' && !seenPoint) {
      seenPoint = true;
    } else {
      break;
    }
  }
  auto malformed = [&](size_t end) {
    throw ParseError(columnOf(text, static_cast<int>(start)),
                     "malformed number '" + std::string(text.substr(start, end - start)) + "'");
  };
  if (mantissaDigits == 0) malformed(i);
  long exponent = 0;
  if (i < text.size() && (text[i] == 'e' || text[i] == 'E')) {
    size_t j = i + 1;
    bool negative = false;
    if (j < text.size() && (text[j] == '+' || text[j] == '-')) negative = text[j++] == '-';
    const size_t expStart = j;
    while (j < text.size() && isDigit(text[j])) {
      if (exponent < 100000) exponent = exponent * 10 + (text[j] - '0');
      ++j;
    }
    if (j == expStart) malformed(j);  // "2e", "1e+": an exponent needs digits
    if (negative) exponent = -exponent;
    i = j;
  }
  // A letter or a second point glued to the literal ("2x", "1.2.3") is a typo, not a
  // product: say so here rather than as a missing operator.
  if (i < text.size() && (isNameChar(text[i]) || text[i] == '.')) {
    size_t j = i;
    while (j < text.size() && (isNameChar(text[j]) || text[j] == '.')) ++j;
    // The hint names the user's own product ("3y" -> 3*y, "2xz" -> 2*x*z) where a name
    // follows the number; a point after the number ("1.2.3", "1e0.5") is no product.
    const std::string_view rest = text.substr(i, j - i);
    std::string product(text.substr(start, i - start));
    if (rest.find_first_not_of("xyz") == std::string_view::npos)
      for (const char c : rest) product += {'*', c};
    else
      product += "*" + std::string(rest);
    const std::string hint = text[i] == '.'
                                 ? " (a number has one decimal point and an integer exponent)"
                                 : " (write a product with '*': " + product + ")";
    throw ParseError(
        columnOf(text, static_cast<int>(start)),
        "malformed number '" + std::string(text.substr(start, j - start)) + "'" + hint);
  }
  Token t{TokenKind::Number, static_cast<int>(start), static_cast<int>(i - start)};
  const char* first = text.data() + start;
  const auto [ptr, ec] = std::from_chars(first, text.data() + i, t.number);
  if (ec == std::errc::result_out_of_range) {
    const long magnitude =
        seenNonZero ? (firstNonZero < 0 ? firstNonZero : digitsBeforePoint) + exponent : 0;
    if (magnitude < 0) {
      t.number = 0.0;  // below the smallest subnormal: the nearest double is 0
    } else {
      throw ParseError(columnOf(text, static_cast<int>(start)),
                       "number '" + std::string(text.substr(start, i - start)) +
                           "' is too large for double (not finite)");
    }
  } else if (ec != std::errc() || ptr != text.data() + i) {
    malformed(i);
  }
  return t;
}

// Typographic forms of the language's symbols, as equations copied from papers and web
// pages carry them (U+2212 for '-' is what most of them print): the minus sign, and the en
// dash U+2013 that word processors make of " - " (an equation has no ranges, so it can
// only be a minus; session 53's user audit; the em dash stays refused: it is no operator
// people type), the dot and cross operators for '*', the division sign, the no-break and
// thin spaces.
struct Typographic {
  std::string_view utf8;
  TokenKind kind;  // End: a space
};
constexpr Typographic kTypographic[] = {
    {"\u2212", TokenKind::Minus}, {"\u2013", TokenKind::Minus}, {"\u00B7", TokenKind::Star},
    {"\u22C5", TokenKind::Star},  {"\u2219", TokenKind::Star},  {"\u00D7", TokenKind::Star},
    {"\u00F7", TokenKind::Slash}, {"\u00A0", TokenKind::End},   {"\u2009", TokenKind::End},
    {"\u202F", TokenKind::End},
};

// The digit of a superscript digit at text[i] (U+2070, U+00B9, U+00B2, U+00B3,
// U+2074..U+2079), or -1; its length in bytes in `length`.
int superscriptDigit(std::string_view text, size_t i, int& length) {
  const auto byte = [&](size_t k) {
    return k < text.size() ? static_cast<unsigned char>(text[k]) : 0u;
  };
  length = 2;
  if (byte(i) == 0xC2) {
    if (byte(i + 1) == 0xB9) return 1;
    if (byte(i + 1) == 0xB2) return 2;
    if (byte(i + 1) == 0xB3) return 3;
    return -1;
  }
  length = 3;
  if (byte(i) == 0xE2 && byte(i + 1) == 0x81) {
    const unsigned c = byte(i + 2);
    if (c == 0xB0) return 0;
    if (c >= 0xB4 && c <= 0xB9) return static_cast<int>(c - 0xB0);
  }
  return -1;
}
bool startsSuperscriptDigit(std::string_view text, size_t i) {
  int length = 0;
  return superscriptDigit(text, i, length) >= 0;
}

// 3 where text[i] is a superscript sign (U+207A, U+207B) that a superscript digit follows,
// else 0: x⁻¹ is x^-1, which the parser then refuses as x^-1 (a constant's 2⁻¹ is 0.5).
size_t superscriptSignLength(std::string_view text, size_t i) {
  const bool sign = text.substr(i).starts_with("\u207A") || text.substr(i).starts_with("\u207B");
  return sign && startsSuperscriptDigit(text, i + 3) ? 3 : 0;
}

// A name written as a typographic letter: the Greek pi (U+03C0, and its italic U+1D70B) and
// the mathematical italic letters of word processors' equations, capital (U+1D434..U+1D44D,
// a torus's R) and small (U+1D44E..U+1D467, with U+210E for h, the Planck constant sign
// Unicode puts in its place; the capitals were refused until session 44).
struct LetterForm {
  std::string_view name;  // empty: none at text[i]
  int length = 0;         // in bytes
};
LetterForm letterForm(std::string_view text, size_t i) {
  static constexpr std::string_view kLetters =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz";
  const std::string_view rest = text.substr(i);
  if (rest.starts_with("\u03C0")) return {"pi", 2};
  if (rest.starts_with("\u210E")) return {"h", 3};
  if (rest.starts_with("\U0001D70B")) return {"pi", 4};
  // F0 9D 90..91 xx: U+1D400..U+1D47F, of which U+1D434..U+1D467 are the italic letters
  // (U+1D455, the italic h's unassigned slot, included: nothing else is there).
  if (rest.size() < 4 || !rest.starts_with("\xF0\x9D")) return {};
  const int third = static_cast<unsigned char>(rest[2]), last = static_cast<unsigned char>(rest[3]);
  if ((third != 0x90 && third != 0x91) || (last & 0xC0) != 0x80) return {};
  const int codePoint = 0x1D000 + ((third & 0x3F) << 6) + (last & 0x3F);
  if (codePoint < 0x1D434 || codePoint > 0x1D467) return {};
  return {kLetters.substr(static_cast<size_t>(codePoint - 0x1D434), 1), 4};
}

// The character at text[i] for a message: quoted as written, with its code point where it
// is not ASCII (an invisible U+FEFF or U+200B in a pasted equation shows as '' otherwise),
// or as \xNN bytes where it is a control character or not valid UTF-8.
std::string shownCharacter(std::string_view text, size_t i) {
  const int n = charLength(text, i);
  const auto byte = [&](int k) { return static_cast<unsigned char>(text[i + k]); };
  // The code point of a well-formed sequence of n bytes (RFC 3629), else -1.
  long code = -1;
  if (n == 1 && byte(0) >= 0x20 && byte(0) != 0x7F && byte(0) < 0x80) {
    code = byte(0);
  } else if (n >= 2 && n <= 4 && byte(0) >= 0xC2 && byte(0) <= 0xF4) {
    const int expected = byte(0) >= 0xF0 ? 4 : byte(0) >= 0xE0 ? 3 : 2;
    code = byte(0) & (0x7F >> expected);
    for (int k = 1; k < n; ++k) code = code << 6 | (byte(k) & 0x3F);
    const long least = n == 2 ? 0x80 : n == 3 ? 0x800 : 0x10000;
    if (n != expected || code < least || code > 0x10FFFF || (code >= 0xD800 && code < 0xE000))
      code = -1;
  }
  char buf[16];
  if (code < 0) {
    std::string bytes;
    for (int k = 0; k < n; ++k) {
      std::snprintf(buf, sizeof buf, "\\x%02X", static_cast<unsigned>(byte(k)));
      bytes += buf;
    }
    return "'" + bytes + "'";
  }
  if (code < 0x80) return "'" + std::string(text.substr(i, 1)) + "'";
  std::snprintf(buf, sizeof buf, "U+%04lX", static_cast<unsigned long>(code));
  return "'" + std::string(text.substr(i, n)) + "' (" + buf + ")";
}

}  // namespace

int columnOf(std::string_view text, int offset) {
  int column = 1;
  for (int i = 0; i < offset && i < static_cast<int>(text.size()); ++i)
    if (!isContinuation(text[i])) ++column;
  return column;
}

std::string describe(std::string_view text, const Token& token) {
  if (token.kind == TokenKind::End) return "the end of the equation";
  return "'" + std::string(text.substr(token.offset, token.length)) + "'";
}

std::vector<Token> tokenize(std::string_view text) {
  std::vector<Token> tokens;
  size_t i = 0;
  while (i < text.size()) {
    const char c = text[i];
    if (isSpace(c)) {
      ++i;
      continue;
    }
    const int at = static_cast<int>(i);
    auto single = [&](TokenKind kind, int length = 1) {
      tokens.push_back({kind, at, length});
      i += length;
    };
    if (isDigit(c) || (c == '.' && i + 1 < text.size() && isDigit(text[i + 1]))) {
      tokens.push_back(readNumber(text, i));
      i += tokens.back().length;
    } else if (isNameStart(c)) {
      size_t j = i;
      while (j < text.size() && isNameChar(text[j])) ++j;
      single(TokenKind::Name, static_cast<int>(j - i));
    } else if (c == '+') {
      single(TokenKind::Plus);
    } else if (c == '-') {
      single(TokenKind::Minus);
    } else if (c == '*') {
      if (i + 1 < text.size() && text[i + 1] == '*')
        single(TokenKind::Caret, 2);
      else
        single(TokenKind::Star);
    } else if (c == '/') {
      single(TokenKind::Slash);
    } else if (c == '^') {
      single(TokenKind::Caret);
    } else if (c == '(') {
      single(TokenKind::LeftParen);
    } else if (c == ')') {
      single(TokenKind::RightParen);
    } else if (c == '=') {
      single(TokenKind::Equals);
    } else if (const LetterForm letter = letterForm(text, i); !letter.name.empty()) {
      tokens.push_back({TokenKind::Name, at, letter.length, 0.0, letter.name});
      i += letter.length;
    } else if (const size_t sign = superscriptSignLength(text, i);
               startsSuperscriptDigit(text, i + sign)) {
      // x² is x^2: a run of superscript digits (after an optional superscript sign) is a
      // '^' spanning the run, the sign, and the exponent (messages show them as written).
      size_t j = i + sign;
      double exponent = 0;
      int digits = 0, length = 0;
      for (int d; (d = superscriptDigit(text, j, length)) >= 0; j += length, ++digits)
        exponent = exponent * 10 + d;
      if (digits > 9)
        throw ParseError(
            columnOf(text, at),
            "superscript exponent '" + std::string(text.substr(i, j - i)) + "' is too large");
      const int span = static_cast<int>(j - i), signSpan = static_cast<int>(sign);
      tokens.push_back({TokenKind::Caret, at, span});
      if (sign > 0)
        tokens.push_back(
            {text[i + 2] == '\xBB' ? TokenKind::Minus : TokenKind::Plus, at, signSpan});
      tokens.push_back({TokenKind::Number, at + signSpan, span - signSpan, exponent});
      i = j;
    } else if (const auto* typo = std::find_if(
                   std::begin(kTypographic), std::end(kTypographic),
                   [&](const Typographic& t) { return text.substr(i).starts_with(t.utf8); });
               typo != std::end(kTypographic)) {
      if (typo->kind == TokenKind::End)
        i += typo->utf8.size();
      else
        single(typo->kind, static_cast<int>(typo->utf8.size()));
    } else {
      std::string hint;
      if (c == '[' || c == '{')
        hint = " (use '(' for grouping)";
      else if (c == ']' || c == '}')
        hint = " (use ')' for grouping)";
      else if (c == ',')
        hint = " (functions take one argument; write decimals with '.')";
      else if (c == '<' || c == '>')
        hint = " (a surface is an equation, f = 0 or lhs = rhs, not an inequality)";
      throw ParseError(columnOf(text, at),
                       "unexpected character " + shownCharacter(text, i) + hint);
    }
  }
  tokens.push_back({TokenKind::End, static_cast<int>(text.size()), 0});
  return tokens;
}

}  // namespace algray::detail
