// Token reader over a whole file held in memory. Tracks the line number of every token so
// readers can throw InputError("file:line: expected ..., got ...") for malformed input.
// Tokens are whitespace separated; a format may set a comment character ('#') that hides the
// rest of its line. Also hands out raw byte ranges for binary blocks inside a text file.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace hapstate {

class TextCursor {
 public:
  // `text` must outlive the cursor; `source` is the file name used in error messages;
  // `first_line` is the line number of text[0] (for a piece of a larger file).
  TextCursor(std::string_view text, std::string source, char comment = '\0', int first_line = 1);

  // True when only whitespace (and comments) remain.
  bool at_end();
  // Next token; throws "expected <what>, got end of file" at the end.
  std::string_view token(std::string_view what);
  // Next token without consuming it ("" at the end).
  std::string_view peek();
  // Next token parsed as an integer / a finite double; throws naming `what` otherwise.
  long long read_int(std::string_view what);
  double read_double(std::string_view what);
  // Consumes the next token, which must equal `keyword`.
  void expect(std::string_view keyword);
  // Rest of the current line (after the last token), trimmed; moves to the next line.
  std::string_view rest_of_line();
  // Consumes exactly one line end (after binary headers); whitespace before it is skipped.
  void skip_line_end();
  // Moves just past the next occurrence of `marker` (e.g. "$EndNodeData"); throws "truncated
  // file: missing <marker>" if there is none.
  void skip_past(std::string_view marker);
  // Raw bytes [offset, offset + n) for a binary block; throws "truncated" if the file ends first.
  const char* take_bytes(std::size_t n, std::string_view what);

  // Line of the last token read (1-based); `where()` is "file:line".
  int line() const { return token_line_; }
  std::string where() const;
  std::string where(int line) const;
  const std::string& source() const { return source_; }
  std::size_t offset() const { return pos_; }
  // How many items of at least `min_bytes` bytes each the rest of the text can hold: what a count
  // the file declares may pre-allocate (a declared count is not trusted before it is read).
  std::size_t capacity(std::size_t min_bytes) const { return (text_.size() - pos_) / min_bytes; }

  // Throws InputError "file:line: message" (line of the last token).
  [[noreturn]] void fail(const std::string& message) const;
  [[noreturn]] void fail_at(int line, const std::string& message) const;
  // Throws "file:line: expected <what>, got '<got>'".
  [[noreturn]] void fail_expected(std::string_view what, std::string_view got) const;

 private:
  void skip_space();

  std::string_view text_;
  std::string source_;
  char comment_;
  std::size_t pos_ = 0;
  int line_ = 1;        // line at pos_
  int token_line_ = 1;  // line of the last token
};

// Parses a whole token as a number; false if it is not one (or not finite).
bool parse_int(std::string_view token, long long* value);
bool parse_double(std::string_view token, double* value);

// Short printable form of a token for error messages (clipped, non-printables escaped).
std::string printable(std::string_view token);

}  // namespace hapstate
