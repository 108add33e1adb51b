#pragma once
// The lines of a text file as both tools read them: algray-query's IN.csv and
// algray-render's OBJ checker (mesh.cpp, which must split lines as tinyobjloader's
// safeGetline does).
#include <istream>
#include <string>
#include <string_view>

namespace algray::text {

// Lines end at "\n", "\r\n" or a lone "\r" (classic Mac OS). Split at "\n" only, a CR-only
// file was one line: IN.csv had "no column 'tfar'", and after an OBJ comment line
// "v abc 1 0" or "f 1 2 4294967299" were never checked (tinyobjloader split them and
// rendered them), while a valid CR-only OBJ file was refused as "'v' with 15 numbers".
class LineReader {
 public:
  explicit LineReader(std::istream& in) : in_(in) {}

  // The next line without its ending, valid until the next call; false after the last (a
  // last line without an ending is a line, an empty rest is none). The file is read in
  // blocks, not in std::getline's pieces up to a '\n': a CR-only file is one such piece,
  // held whole. A read error ends the lines as the end of the file does (the caller tells
  // them apart by the stream's bad()).
  bool next(std::string_view& line) {
    carry_.clear();
    bool carried = false;  // part of the line is in carry_
    for (;;) {
      if (pos_ == block_.size()) {
        block_.resize(kBlock);
        in_.read(block_.data(), kBlock);
        block_.resize(static_cast<size_t>(in_.gcount()));
        pos_ = 0;
        if (block_.empty()) {
          if (carried) ++number_;
          line = carry_;
          return carried;
        }
      }
      if (afterCr_) {  // "\r\n" is one ending, even across two blocks
        afterCr_ = false;
        if (block_[pos_] == '\n' && ++pos_ == block_.size()) continue;
      }
      size_t end = pos_;
      while (end < block_.size() && block_[end] != '\n' && block_[end] != '\r') ++end;
      if (end == block_.size()) {
        carry_.append(block_, pos_, end - pos_);
        carried = true;
        pos_ = end;
        continue;
      }
      const std::string_view piece = std::string_view(block_).substr(pos_, end - pos_);
      afterCr_ = block_[end] == '\r';
      pos_ = end + 1;
      if (!carried) {
        line = piece;
      } else {
        carry_.append(piece);
        line = carry_;
      }
      ++number_;
      return true;
    }
  }
  // The 1-based number of the line next() returned last (0 before the first).
  long long number() const { return number_; }

 private:
  static constexpr size_t kBlock = 1 << 16;
  std::istream& in_;
  std::string block_;  // the block read last, lines from pos_ on not returned yet
  size_t pos_ = 0;
  std::string carry_;     // a line begun in an earlier block
  bool afterCr_ = false;  // the last line ended in '\r': a '\n' next belongs to it
  long long number_ = 0;
};

}  // namespace algray::text
