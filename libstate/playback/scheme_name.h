// The names of the interpolation schemes (hapstate::Scheme, include/hapstate/playback.h) as the
// commands, the reports, the CSV columns, the certificate's keys and the Python binding write
// and read them: the one definition.
#pragma once

#include "hapstate/playback.h"

#include <optional>
#include <string_view>

namespace hapstate {

inline constexpr int kNumSchemes = 2;

// "trilinear" or "hermite" (the index of a scheme is its enum value: kTrilinear 0, kHermite 1).
constexpr const char* scheme_name(Scheme scheme) {
  return scheme == Scheme::kTrilinear ? "trilinear" : "hermite";
}
constexpr const char* scheme_name(int index) { return scheme_name(static_cast<Scheme>(index)); }

// The scheme with that name, or none.
constexpr std::optional<Scheme> parse_scheme(std::string_view name) {
  for (const Scheme s : {Scheme::kTrilinear, Scheme::kHermite})
    if (name == scheme_name(s)) return s;
  return std::nullopt;
}

}  // namespace hapstate
