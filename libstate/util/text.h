// Small text helpers shared by the line-oriented readers and the solver's messages.
#pragma once

#include <cstdio>
#include <string>
#include <string_view>

namespace hapstate {

// `s` without leading and trailing spaces, tabs and carriage returns.
inline std::string trim(std::string_view s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string_view::npos) return "";
  const auto e = s.find_last_not_of(" \t\r");
  return std::string(s.substr(b, e - b + 1));
}

// `v` in scientific notation with 4 significant digits ("1.694e-03").
inline std::string sci(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3e", v);
  return buf;
}

}  // namespace hapstate
