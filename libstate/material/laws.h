// Internal constructors of the concrete laws; use make_material() from outside the module.
// Constants are validated by make_material() before these are called.
#pragma once

#include "material/material.h"

#include <memory>

namespace hapstate::detail {

std::unique_ptr<Material> make_linear(double mu, double lambda);
std::unique_ptr<Material> make_stvk(double mu, double lambda);
std::unique_ptr<Material> make_neohooke(double c10, double d1);
std::unique_ptr<Material> make_mooney(double c10, double c01, double d1);

}  // namespace hapstate::detail
