#include "scene/bind.h"

namespace hapstate {

MaterialConstants resolve_material(const SceneMaterial& m) {
  if (m.young && m.poisson) return constants_from_young_poisson(m.law, *m.young, *m.poisson);
  MaterialConstants c;
  c.law = m.law;
  switch (m.law) {
    case Law::kLinear:
    case Law::kStvk: {
      c.mu = m.mu.value_or(0);
      c.lambda = m.lambda.value_or(0);
      c.c10 = c.mu / 2;
      c.d1 = 2 / (c.lambda + 2 * c.mu / 3);
      break;
    }
    case Law::kNeoHooke:
    case Law::kMooney: {
      c.c10 = m.c10.value_or(0);
      c.c01 = m.law == Law::kMooney ? m.c01.value_or(0) : 0.0;
      c.d1 = m.d1.value_or(0);
      c.mu = 2 * (c.c10 + c.c01);
      c.lambda = 2 / c.d1 - 2 * c.mu / 3;
      break;
    }
  }
  return c;
}

}  // namespace hapstate
