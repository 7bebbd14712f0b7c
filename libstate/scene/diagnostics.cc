#include "scene/diagnostics.h"

#include "util/error.h"

#include <algorithm>
#include <climits>
#include <tuple>

namespace hapstate {

void Diagnostics::add(int line, std::string message) { add_in(file_, line, std::move(message)); }

void Diagnostics::add_in(const std::string& file, int line, std::string message) {
  entries_.push_back({file, line, std::move(message), count()});
}

void Diagnostics::add_cause(int line, std::string message) {
  entries_.push_back({file_, line, std::move(message), count(), true});
}

std::string Diagnostics::message() const {
  std::vector<const Entry*> sorted;
  for (const Entry& e : entries_) sorted.push_back(&e);
  auto key = [this](const Entry* e) {
    const bool own = e->file == file_;
    const int line = own ? (e->line > 0 ? e->line : INT_MAX - 1) : INT_MAX;
    return std::tuple{!e->cause, line, e->order};
  };
  std::sort(sorted.begin(), sorted.end(),
            [&](const Entry* a, const Entry* b) { return key(a) < key(b); });
  std::string out;
  for (const Entry* e : sorted) {
    if (!out.empty()) out += '\n';
    out += e->file;
    if (e->line > 0) out += ':' + std::to_string(e->line);
    out += ": " + e->text;
  }
  return out;
}

void Diagnostics::throw_if_any() const {
  if (!empty()) throw InputError(message());
}

}  // namespace hapstate
