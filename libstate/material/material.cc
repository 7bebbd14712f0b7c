// Law names, constants from (E, nu), validation and the factory.
#include "material/material.h"

#include "material/laws.h"
#include "util/error.h"

#include <cmath>
#include <sstream>

namespace hapstate {
namespace {

constexpr Law kAllLaws[] = {Law::kLinear, Law::kStvk, Law::kNeoHooke, Law::kMooney};

[[noreturn]] void fail(std::string_view law, std::string_view parameter, double value,
                       std::string_view allowed) {
  std::ostringstream msg;
  msg << "material '" << law << "': " << parameter << " = " << value << " is out of range, "
      << "allowed " << allowed;
  throw InputError(msg.str());
}

void require(bool ok, std::string_view law, std::string_view parameter, double value,
             std::string_view allowed) {
  if (!ok) fail(law, parameter, value, allowed);
}

void validate(const MaterialConstants& c) {
  const std::string_view law = law_name(c.law);
  switch (c.law) {
    case Law::kLinear:
    case Law::kStvk:
      require(std::isfinite(c.mu) && c.mu > 0, law, "mu", c.mu, "0 < mu < inf [Pa]");
      require(std::isfinite(c.lambda) && c.lambda + 2.0 / 3.0 * c.mu > 0, law, "lambda", c.lambda,
              "lambda > -2/3 mu (positive bulk modulus), finite [Pa]");
      return;
    case Law::kMooney:
      require(std::isfinite(c.c01) && c.c01 >= 0, law, "c01", c.c01, "0 <= c01 < inf [Pa]");
      [[fallthrough]];
    case Law::kNeoHooke:
      require(std::isfinite(c.c10) && c.c10 > 0, law, "c10", c.c10, "0 < c10 < inf [Pa]");
      require(std::isfinite(c.d1) && c.d1 > 0, law, "d1", c.d1, "0 < d1 < inf [1/Pa]");
      return;
  }
  throw InputError("material: unknown law enumerator " + std::to_string(static_cast<int>(c.law)));
}

}  // namespace

MaterialConstants constants_from_young_poisson(Law law, double young, double poisson) {
  const std::string_view name = law_name(law);
  require(std::isfinite(young) && young > 0, name, "young (E)", young, "0 < E < inf [Pa]");
  require(poisson > -1.0 && poisson < 0.5, name, "poisson (nu)", poisson, "-1 < nu < 0.5");
  MaterialConstants c;
  c.law = law;
  c.mu = young / (2.0 * (1.0 + poisson));
  c.lambda = young * poisson / ((1.0 + poisson) * (1.0 - 2.0 * poisson));
  const double bulk = young / (3.0 * (1.0 - 2.0 * poisson));
  c.d1 = 2.0 / bulk;
  if (law == Law::kMooney) {
    c.c10 = kMooneyC10Share * c.mu / 2.0;
    c.c01 = (1.0 - kMooneyC10Share) * c.mu / 2.0;
  } else {
    c.c10 = c.mu / 2.0;
  }
  return c;
}

std::unique_ptr<Material> make_material(const MaterialConstants& c) {
  validate(c);
  switch (c.law) {
    case Law::kLinear:
      return detail::make_linear(c.mu, c.lambda);
    case Law::kStvk:
      return detail::make_stvk(c.mu, c.lambda);
    case Law::kNeoHooke:
      return detail::make_neohooke(c.c10, c.d1);
    case Law::kMooney:
      return detail::make_mooney(c.c10, c.c01, c.d1);
  }
  throw InputError("material: unknown law enumerator");  // unreachable after validate()
}

std::string_view law_name(Law law) {
  switch (law) {
    case Law::kLinear:
      return "linear";
    case Law::kStvk:
      return "stvk";
    case Law::kNeoHooke:
      return "neohooke";
    case Law::kMooney:
      return "mooney";
  }
  throw InputError("material: unknown law enumerator " + std::to_string(static_cast<int>(law)));
}

Law law_from_name(std::string_view name) {
  std::string known;
  for (Law law : kAllLaws) {
    if (law_name(law) == name) return law;
    known += (known.empty() ? "" : ", ") + std::string(law_name(law));
  }
  throw InputError("material: unknown law '" + std::string(name) + "' (known: " + known + ")");
}

}  // namespace hapstate
