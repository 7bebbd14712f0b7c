// Constants from (E, nu), names, and rejection of invalid constants.
#include "material/material.h"
#include "util/error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

namespace hapstate {
namespace {

// E = 2.6, nu = 0.3: mu = 1, lambda = 0.78 / 0.52 = 1.5, K = 2.6 / 1.2, d1 = 2.4 / 2.6.
TEST(Constants, FromYoungPoissonByHand) {
  const MaterialConstants stvk = constants_from_young_poisson(Law::kStvk, 2.6, 0.3);
  EXPECT_EQ(stvk.law, Law::kStvk);
  EXPECT_NEAR(stvk.mu, 1.0, 1e-15);
  EXPECT_NEAR(stvk.lambda, 1.5, 1e-14);

  const MaterialConstants neo = constants_from_young_poisson(Law::kNeoHooke, 2.6, 0.3);
  EXPECT_NEAR(neo.c10, 0.5, 1e-15);
  EXPECT_NEAR(neo.d1, 2.4 / 2.6, 1e-15);
  EXPECT_EQ(neo.c01, 0.0);

  const MaterialConstants mooney = constants_from_young_poisson(Law::kMooney, 2.6, 0.3);
  EXPECT_NEAR(mooney.c10, 0.4, 1e-15);
  EXPECT_NEAR(mooney.c01, 0.1, 1e-15);
  EXPECT_NEAR(mooney.d1, 2.4 / 2.6, 1e-15);
}

TEST(Constants, NamesRoundTrip) {
  for (Law law : {Law::kLinear, Law::kStvk, Law::kNeoHooke, Law::kMooney}) {
    EXPECT_EQ(law_from_name(law_name(law)), law);
    const auto material = make_material(constants_from_young_poisson(law, 1e3, 0.3));
    EXPECT_EQ(material->name(), law_name(law));
  }
  EXPECT_EQ(law_name(Law::kNeoHooke), "neohooke");
  EXPECT_THROW(law_from_name("neo-hooke"), InputError);
  EXPECT_THROW(law_from_name(""), InputError);
}

TEST(Constants, PositiveJacobianRequirement) {
  auto needs = [](Law law) {
    return make_material(constants_from_young_poisson(law, 1e3, 0.3))->requires_positive_jacobian();
  };
  EXPECT_FALSE(needs(Law::kLinear));
  EXPECT_FALSE(needs(Law::kStvk));
  EXPECT_TRUE(needs(Law::kNeoHooke));
  EXPECT_TRUE(needs(Law::kMooney));
}

// The call must throw InputError whose message names `parameter`.
template <class Fn>
void expect_rejected(const Fn& fn, const std::string& parameter) {
  try {
    fn();
    ADD_FAILURE() << "no InputError for bad " << parameter;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(parameter), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("allowed"), std::string::npos) << e.what();
  }
}

TEST(Constants, InvalidYoungPoissonThrows) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (double young : {0.0, -1.0, nan, inf})
    expect_rejected([&] { constants_from_young_poisson(Law::kStvk, young, 0.3); }, "young");
  for (double nu : {0.5, 0.7, -1.0, -2.0, nan})
    expect_rejected([&] { constants_from_young_poisson(Law::kNeoHooke, 1e3, nu); }, "poisson");
  EXPECT_NO_THROW(constants_from_young_poisson(Law::kMooney, 1e3, 0.499));
  EXPECT_NO_THROW(constants_from_young_poisson(Law::kMooney, 1e3, -0.5));
}

TEST(Constants, InvalidDirectConstantsThrow) {
  auto with = [](Law law, double mu, double lambda, double c10, double c01, double d1) {
    MaterialConstants c;
    c.law = law;
    c.mu = mu;
    c.lambda = lambda;
    c.c10 = c10;
    c.c01 = c01;
    c.d1 = d1;
    return [c] { make_material(c); };
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (Law law : {Law::kLinear, Law::kStvk}) {
    expect_rejected(with(law, 0, 1, 0, 0, 0), "mu");
    expect_rejected(with(law, -1, 1, 0, 0, 0), "mu");
    expect_rejected(with(law, nan, 1, 0, 0, 0), "mu");
    expect_rejected(with(law, 3, -2.5, 0, 0, 0), "lambda");  // bulk = -0.5
    EXPECT_NO_THROW(with(law, 3, -1.5, 0, 0, 0)());          // bulk = 0.5
  }
  for (Law law : {Law::kNeoHooke, Law::kMooney}) {
    expect_rejected(with(law, 0, 0, 0, 0, 1), "c10");
    expect_rejected(with(law, 0, 0, -1, 0, 1), "c10");
    expect_rejected(with(law, 0, 0, 1, 0, 0), "d1");
    expect_rejected(with(law, 0, 0, 1, 0, nan), "d1");
    EXPECT_NO_THROW(with(law, 0, 0, 1, 0, 1)());
  }
  expect_rejected(with(Law::kMooney, 0, 0, 1, -0.1, 1), "c01");
  EXPECT_THROW(make_material(MaterialConstants{}), InputError);  // default stvk, mu = 0
}

}  // namespace
}  // namespace hapstate
