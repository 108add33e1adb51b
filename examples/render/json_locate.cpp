#include "json_locate.h"

#include <cctype>

namespace algray::render {

TextLocation locateOffset(std::string_view text, size_t offset) {
  TextLocation loc;
  for (size_t i = 0; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++loc.line;
      loc.column = 1;
    } else {
      ++loc.column;
    }
  }
  return loc;
}

namespace {

class Scanner {
 public:
  Scanner(std::string_view text, std::map<std::string, size_t>& out) : s_(text), out_(out) {}

  void value(const std::string& pointer) {
    skipSpace();
    if (i_ >= s_.size()) return;
    out_[pointer] = i_;
    char c = s_[i_];
    if (c == '{') {
      ++i_;
      skipSpace();
      if (peek('}')) return void(++i_);
      while (i_ < s_.size()) {
        skipSpace();
        std::string key = string();
        skipSpace();
        if (!peek(':')) return;
        ++i_;
        value(pointer + "/" + escape(key));
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
  // A string token; escapes are kept only as far as keys need them (\" and \\).
  std::string string() {
    std::string r;
    if (!peek('"')) return r;
    ++i_;
    while (i_ < s_.size() && s_[i_] != '"') {
      if (s_[i_] == '\\' && i_ + 1 < s_.size()) ++i_;
      r += s_[i_++];
    }
    ++i_;
    return r;
  }
  // RFC 6901: '~' -> "~0", '/' -> "~1".
  static std::string escape(const std::string& key) {
    std::string r;
    for (char c : key) {
      if (c == '~') r += "~0";
      else if (c == '/') r += "~1";
      else r += c;
    }
    return r;
  }

  std::string_view s_;
  std::map<std::string, size_t>& out_;
  size_t i_ = 0;
};

}  // namespace

std::map<std::string, size_t> locateJsonValues(std::string_view text) {
  std::map<std::string, size_t> out;
  Scanner(text, out).value("");
  return out;
}

}  // namespace algray::render
