// Collects located problems (scene, node lists, binding) so that all of them are reported at
// once in a single InputError, one line per problem, ordered by line.
#pragma once

#include <string>
#include <vector>

namespace hapstate {

class Diagnostics {
 public:
  // `file` prefixes every line ("file:LINE: message", or "file: message" for line 0).
  explicit Diagnostics(std::string file) : file_(std::move(file)) {}

  // Records a problem at `line` (1-based; 0 = the whole file) of this object's file.
  void add(int line, std::string message);
  // Records a problem in another file (e.g. a node list read on the scene's behalf).
  void add_in(const std::string& file, int line, std::string message);
  // Records a problem that likely causes others (a misspelt key, whose correct spelling is then
  // reported missing): listed before every other problem, so that the first line names the cause.
  void add_cause(int line, std::string message);

  bool empty() const { return entries_.empty(); }
  int count() const { return static_cast<int>(entries_.size()); }
  const std::string& file() const { return file_; }

  // One line per problem: causes first, then scene-file problems ordered by line (whole-file
  // ones last), then other files in the order they were added.
  std::string message() const;
  // Throws InputError(message()) if any problem was recorded.
  void throw_if_any() const;

 private:
  struct Entry {
    std::string file;
    int line;
    std::string text;
    int order;
    bool cause = false;
  };
  std::string file_;
  std::vector<Entry> entries_;
};

}  // namespace hapstate
