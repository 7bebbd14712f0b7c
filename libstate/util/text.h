// Small text helpers shared by the line-oriented readers and the solver's messages.
#pragma once

#include <cmath>
#include <cstdio>
#include <cstdlib>
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

// A relative error `fraction` as a percentage that never reads 0 for a non-zero value: two
// decimals from 0.01 % up ("0.43 %"), two significant digits below ("0.0012 %", "0.000045 %"),
// "< 1e-8 %" below that; "0 %" only for exactly zero (issue 42: "0.00 %" looked like a bug).
inline std::string percent(double fraction) {
  const double p = 100 * fraction;
  char buf[48];
  if (p == 0) return "0 %";
  if (!(p == p)) return "nan %";
  const double a = p < 0 ? -p : p;
  if (a >= 0.01 || a > 1e300) {
    std::snprintf(buf, sizeof buf, "%.2f %%", p);
  } else if (a < 1e-8) {
    return "< 1e-8 %";
  } else {
    // Two significant digits: round to them first, then as many decimals as they need.
    std::snprintf(buf, sizeof buf, "%.1e", a);
    const double rounded = std::strtod(buf, nullptr);
    const int decimals = static_cast<int>(std::floor(-std::log10(rounded) - 1e-9)) + 2;
    std::snprintf(buf, sizeof buf, "%.*f %%", decimals, p);
  }
  return buf;
}

// "1 segment file", "3 segment files": `n` and the noun in the number it needs.
inline std::string plural(long long n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

// A size in bytes for a reader: "17.3 MiB", "35.2 KiB", "512 B" (binary units).
inline std::string size_text(long long bytes) {
  char buf[32];
  if (bytes >= (1 << 20))
    std::snprintf(buf, sizeof buf, "%.1f MiB", static_cast<double>(bytes) / 1048576.0);
  else if (bytes >= 1024)
    std::snprintf(buf, sizeof buf, "%.1f KiB", static_cast<double>(bytes) / 1024.0);
  else
    std::snprintf(buf, sizeof buf, "%lld B", bytes);
  return buf;
}

}  // namespace hapstate
