// Test helpers for scene tests: a scratch folder with files, and parse-error capture.
#pragma once

#include "scene/scene.h"
#include "util/error.h"

#include <filesystem>
#include <string>

namespace hapstate::testing {

// A fresh folder under the system temp dir, removed when destroyed.
class ScratchDir {
 public:
  ScratchDir();
  ~ScratchDir();
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  // Writes `text` to path()/name and returns the full path.
  std::filesystem::path write(const std::string& name, const std::string& text) const;

 private:
  std::filesystem::path path_;
};

// Replaces the first occurrence of `from` in `text` by `to`; fails the test if absent.
std::string replace_once(std::string text, const std::string& from, const std::string& to);

// The InputError message thrown by `f`, or "<no error>" / "<other exception: ...>".
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  } catch (const std::exception& e) {
    return std::string("<other exception: ") + e.what() + ">";
  }
  return "<no error>";
}

}  // namespace hapstate::testing
