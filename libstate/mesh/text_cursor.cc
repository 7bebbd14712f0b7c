#include "mesh/text_cursor.h"

#include "util/error.h"

#include <charconv>
#include <cmath>
#include <cstring>

namespace hapstate {

TextCursor::TextCursor(std::string_view text, std::string source, char comment, int first_line)
    : text_(text),
      source_(std::move(source)),
      comment_(comment),
      line_(first_line),
      token_line_(first_line) {}

void TextCursor::skip_space() {
  const std::size_t n = text_.size();
  while (pos_ < n) {
    const char c = text_[pos_];
    if (c == '\n') {
      ++line_;
      ++pos_;
    } else if (c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v') {
      ++pos_;
    } else if (comment_ != '\0' && c == comment_) {
      while (pos_ < n && text_[pos_] != '\n') ++pos_;
    } else {
      break;
    }
  }
}

bool TextCursor::at_end() {
  skip_space();
  return pos_ >= text_.size();
}

std::string_view TextCursor::token(std::string_view what) {
  skip_space();
  token_line_ = line_;
  if (pos_ >= text_.size()) {
    // Name the last line that has content.
    if (!text_.empty() && text_.back() == '\n' && token_line_ > 1) --token_line_;
    fail("expected " + std::string(what) + ", got end of file (truncated file?)");
  }
  const std::size_t begin = pos_;
  const std::size_t n = text_.size();
  while (pos_ < n) {
    const char c = text_[pos_];
    if (c == ' ' || c == '\n' || c == '\t' || c == '\r' || c == '\f' || c == '\v') break;
    if (comment_ != '\0' && c == comment_) break;
    ++pos_;
  }
  return text_.substr(begin, pos_ - begin);
}

std::string_view TextCursor::peek() {
  skip_space();
  std::size_t end = pos_;
  while (end < text_.size()) {
    const char c = text_[end];
    if (c == ' ' || c == '\n' || c == '\t' || c == '\r' || c == '\f' || c == '\v') break;
    if (comment_ != '\0' && c == comment_) break;
    ++end;
  }
  return text_.substr(pos_, end - pos_);
}

long long TextCursor::read_int(std::string_view what) {
  const std::string_view t = token(what);
  long long v = 0;
  if (!parse_int(t, &v)) fail_expected(std::string(what) + " (an integer)", t);
  return v;
}

double TextCursor::read_double(std::string_view what) {
  const std::string_view t = token(what);
  double v = 0;
  if (!parse_double(t, &v)) fail_expected(std::string(what) + " (a finite number)", t);
  return v;
}

void TextCursor::expect(std::string_view keyword) {
  const std::string_view t = token(keyword);
  if (t != keyword) {
    std::string quoted;  // (built by append: GCC 12 -O3 warns falsely on "'" + std::string)
    quoted.append(1, '\'').append(keyword).append(1, '\'');
    fail_expected(quoted, t);
  }
}

std::string_view TextCursor::rest_of_line() {
  const std::size_t n = text_.size();
  std::size_t end = pos_;
  while (end < n && text_[end] != '\n') ++end;
  std::string_view s = text_.substr(pos_, end - pos_);
  pos_ = end;
  while (!s.empty() && std::strchr(" \t\r", s.front()) != nullptr) s.remove_prefix(1);
  while (!s.empty() && std::strchr(" \t\r", s.back()) != nullptr) s.remove_suffix(1);
  return s;
}

void TextCursor::skip_line_end() {
  while (pos_ < text_.size() && (text_[pos_] == ' ' || text_[pos_] == '\t' || text_[pos_] == '\r'))
    ++pos_;
  if (pos_ < text_.size() && text_[pos_] == '\n') {
    ++pos_;
    ++line_;
  }
}

const char* TextCursor::take_bytes(std::size_t n, std::string_view what) {
  token_line_ = line_;
  if (n > text_.size() - pos_) {
    fail("truncated file: expected " + std::to_string(n) + " bytes of binary " + std::string(what) +
         ", only " + std::to_string(text_.size() - pos_) + " left");
  }
  const char* p = text_.data() + pos_;
  for (std::size_t i = 0; i < n; ++i) line_ += p[i] == '\n';
  pos_ += n;
  return p;
}

void TextCursor::skip_past(std::string_view marker) {
  const std::size_t found = text_.find(marker, pos_);
  if (found == std::string_view::npos)
    fail("truncated file: missing '" + std::string(marker) + "'");
  take_bytes(found + marker.size() - pos_, marker);
}

std::string TextCursor::where() const { return where(token_line_); }
std::string TextCursor::where(int line) const { return source_ + ":" + std::to_string(line); }

void TextCursor::fail(const std::string& message) const { fail_at(token_line_, message); }

void TextCursor::fail_at(int line, const std::string& message) const {
  throw InputError(where(line) + ": " + message);
}

void TextCursor::fail_expected(std::string_view what, std::string_view got) const {
  fail("expected " + std::string(what) + ", got '" + printable(got) + "'");
}

bool parse_int(std::string_view t, long long* value) {
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), *value);
  return ec == std::errc() && end == t.data() + t.size() && !t.empty();
}

bool parse_double(std::string_view t, double* value) {
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), *value);
  return ec == std::errc() && end == t.data() + t.size() && !t.empty() && std::isfinite(*value);
}

std::string printable(std::string_view t) {
  std::string out;
  for (std::size_t i = 0; i < t.size() && i < 40; ++i) {
    const unsigned char c = static_cast<unsigned char>(t[i]);
    if (c >= 32 && c < 127) {
      out += static_cast<char>(c);
    } else {
      static const char* kHex = "0123456789abcdef";
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 15];
    }
  }
  if (t.size() > 40) out += "...";
  return out;
}

}  // namespace hapstate
