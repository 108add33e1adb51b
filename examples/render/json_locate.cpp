#include "json_locate.h"

#include <algorithm>
#include <cctype>

namespace algray::render {

TextLocation locateOffset(std::string_view text, size_t offset) {
  TextLocation loc;
  for (size_t i = 0; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++loc.line;
      loc.column = 1;
    } else if ((static_cast<unsigned char>(text[i]) & 0xC0) != 0x80) {
      ++loc.column;  // a character's first byte: columns count characters, as editors do
    }
  }
  return loc;
}

namespace {

class Scanner {
 public:
  Scanner(std::string_view text, std::map<std::string, size_t>& out,
          std::vector<DuplicateKey>* duplicates)
      : s_(text), out_(out), duplicates_(duplicates) {}

  void value(const std::string& pointer) {
    skipSpace();
    if (i_ >= s_.size()) return;
    out_[pointer] = i_;
    char c = s_[i_];
    if (c == '{') {
      ++i_;
      skipSpace();
      if (peek('}')) return void(++i_);
      std::map<std::string, size_t> keys;  // key -> offset of its string, for duplicates
      while (i_ < s_.size()) {
        skipSpace();
        const size_t keyStart = i_;
        std::string key = string();
        const std::string child = pointer + "/" + jsonPointerToken(key);
        if (auto [it, fresh] = keys.emplace(key, keyStart); !fresh && duplicates_)
          duplicates_->push_back({child, key, it->second, keyStart});
        skipSpace();
        if (!peek(':')) return;
        ++i_;
        value(child);
        skipSpace();
        if (peek(',')) {
          ++i_;
          continue;
        }
        if (peek('}')) ++i_;
        return;
      }
    } else if (c == '[') {
      ++i_;
      skipSpace();
      if (peek(']')) return void(++i_);
      for (int index = 0; i_ < s_.size(); ++index) {
        value(pointer + "/" + std::to_string(index));
        skipSpace();
        if (peek(',')) {
          ++i_;
          continue;
        }
        if (peek(']')) ++i_;
        return;
      }
    } else if (c == '"') {
      string();
    } else {
      while (i_ < s_.size() && !std::isspace(static_cast<unsigned char>(s_[i_])) && s_[i_] != ',' &&
             s_[i_] != '}' && s_[i_] != ']')
        ++i_;
    }
  }

 private:
  bool peek(char c) const { return i_ < s_.size() && s_[i_] == c; }
  void skipSpace() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) ++i_;
  }
  // A string token, decoded as nlohmann decodes it (keys must compare equal to its keys).
  std::string string() {
    std::string r;
    if (!peek('"')) return r;
    ++i_;
    while (i_ < s_.size() && s_[i_] != '"') {
      if (s_[i_] != '\\' || i_ + 1 >= s_.size()) {
        r += s_[i_++];
        continue;
      }
      const char e = s_[i_ + 1];
      i_ += 2;
      switch (e) {
        case 'b':
          r += '\b';
          break;
        case 'f':
          r += '\f';
          break;
        case 'n':
          r += '\n';
          break;
        case 'r':
          r += '\r';
          break;
        case 't':
          r += '\t';
          break;
        case 'u':
          appendUtf8(r, codePoint());
          break;
        default:
          r += e;  // \" \\ \/
      }
    }
    ++i_;
    return r;
  }
  // The XXXX of \uXXXX at i_ (a surrogate pair joined with the \uXXXX after it).
  unsigned codePoint() {
    auto hex4 = [&](unsigned& v) {
      if (i_ + 4 > s_.size()) return false;
      v = 0;
      for (int k = 0; k < 4; ++k) {
        const char c = s_[i_ + k];
        const int d = std::isdigit(static_cast<unsigned char>(c)) ? c - '0'
                      : std::isxdigit(static_cast<unsigned char>(c))
                          ? std::tolower(static_cast<unsigned char>(c)) - 'a' + 10
                          : -1;
        if (d < 0) return false;
        v = v * 16 + static_cast<unsigned>(d);
      }
      i_ += 4;
      return true;
    };
    unsigned v = 0;
    if (!hex4(v)) return 0xFFFD;
    if (v >= 0xD800 && v < 0xDC00 && i_ + 6 <= s_.size() && s_[i_] == '\\' && s_[i_ + 1] == 'u') {
      i_ += 2;
      unsigned low = 0;
      if (hex4(low) && low >= 0xDC00 && low < 0xE000)
        return 0x10000 + ((v - 0xD800) << 10) + (low - 0xDC00);
    }
    return v;
  }
  static void appendUtf8(std::string& r, unsigned c) {
    if (c < 0x80) {
      r += static_cast<char>(c);
    } else if (c < 0x800) {
      r += static_cast<char>(0xC0 | (c >> 6));
      r += static_cast<char>(0x80 | (c & 0x3F));
    } else if (c < 0x10000) {
      r += static_cast<char>(0xE0 | (c >> 12));
      r += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
      r += static_cast<char>(0x80 | (c & 0x3F));
    } else {
      r += static_cast<char>(0xF0 | (c >> 18));
      r += static_cast<char>(0x80 | ((c >> 12) & 0x3F));
      r += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
      r += static_cast<char>(0x80 | (c & 0x3F));
    }
  }

  std::string_view s_;
  std::map<std::string, size_t>& out_;
  std::vector<DuplicateKey>* duplicates_;
  size_t i_ = 0;
};

}  // namespace

std::map<std::string, size_t> locateJsonValues(std::string_view text,
                                               std::vector<DuplicateKey>* duplicates) {
  std::map<std::string, size_t> out;
  Scanner(text, out, duplicates).value("");
  return out;
}

std::string jsonPointerToken(std::string_view key) {
  std::string r;
  for (char c : key) {
    if (c == '~')
      r += "~0";
    else if (c == '/')
      r += "~1";
    else
      r += c;
  }
  return r;
}

size_t findExcessiveNesting(std::string_view text, int maxDepth) {
  int depth = 0;
  bool inString = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (inString) {
      if (c == '\\')
        ++i;  // the escaped character cannot end the string
      else if (c == '"')
        inString = false;
    } else if (c == '"') {
      inString = true;
    } else if (c == '[' || c == '{') {
      if (++depth > maxDepth) return i;
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return std::string_view::npos;
}

size_t locateNumberLiteral(std::string_view text, std::string_view literal) {
  auto numberChar = [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == '+';
  };
  for (size_t i = 0; i < text.size();) {
    if (text[i] == '"') {  // skip the string, escapes included
      for (++i; i < text.size() && text[i] != '"'; ++i)
        if (text[i] == '\\') ++i;
      ++i;
    } else if (numberChar(text[i])) {
      size_t end = i;
      while (end < text.size() && numberChar(text[end])) ++end;
      if (text.substr(i, end - i) == literal) return i;
      i = end;
    } else {
      ++i;
    }
  }
  return std::string_view::npos;
}

size_t stringCharacterOffset(std::string_view text, size_t quote, int column) {
  const auto continuation = [&](size_t k) {
    return k < text.size() && (static_cast<unsigned char>(text[k]) & 0xC0) == 0x80;
  };
  const auto unicodeEscape = [&](size_t k) {
    return k + 6 <= text.size() && text[k] == '\\' && text[k + 1] == 'u';
  };
  size_t i = quote + 1;
  for (int c = 1; c < column && i < text.size() && text[i] != '"'; ++c) {
    if (text[i] != '\\') {  // one character: its lead byte and continuation bytes
      ++i;
      while (continuation(i)) ++i;
    } else if (unicodeEscape(i)) {  // \uXXXX, or a surrogate pair \uD8xx\uDCxx: one code point
      const bool high = (text[i + 2] == 'd' || text[i + 2] == 'D') &&
                        std::string_view("89abAB").find(text[i + 3]) != std::string_view::npos;
      i += 6;
      if (high && unicodeEscape(i)) i += 6;
    } else {
      i += 2;  // \n, \", ...
    }
  }
  return std::min(i, text.size());
}

}  // namespace algray::render
