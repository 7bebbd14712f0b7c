// The certificate's report (maintenance/certificate_report.h): the stale line, and the pointer to
// what to change when a scheme is outside the paper's bounds. Truth: the bounds (force 4 %,
// deformation 14 %) and the certificate given.
#include "maintenance/certificate_report.h"
#include "playback/code_id.h"

#include <gtest/gtest.h>

#include <limits>
#include <string>

namespace hapstate {
namespace {

Certificate certificate(double hermite, double trilinear, double deformation) {
  Certificate c;
  c.present = true;
  c.stale = false;
  c.paths = 20;
  c.steps_per_path = 30;
  c.steps = 600;
  c.schemes[1].worst = hermite;
  c.schemes[0].worst = trilinear;
  c.schemes[0].deformation_worst = deformation;
  return c;
}

bool points_to_the_remedy(const Certificate& c) {
  return certificate_text(c).text.find("When it is not good enough") != std::string::npos;
}

TEST(CertificateReport, PointsToTheRemedyOnlyOutsideThePapersBounds) {
  EXPECT_FALSE(points_to_the_remedy(certificate(0.015, 0.03, 0.05)));
  EXPECT_FALSE(points_to_the_remedy(certificate(0.04, 0.04, 0.14)));  // on the bounds: within
  EXPECT_TRUE(points_to_the_remedy(certificate(0.041, 0.03, 0.05)));
  EXPECT_TRUE(points_to_the_remedy(certificate(0.01, 0.055, 0.05)));
  EXPECT_TRUE(points_to_the_remedy(certificate(0.01, 0.02, 0.2)));
  EXPECT_TRUE(points_to_the_remedy(
      certificate(0.01, std::numeric_limits<double>::infinity(), 0.05)));  // a non-finite force
}

TEST(CertificateReport, StaleNamesFileAndCode) {
  Certificate c = certificate(0.01, 0.02, 0.05);
  c.stale = true;
  const std::string text = certificate_text(c).text;
  EXPECT_NE(text.find("STALE, measured on another playback file or by another version of the "
                      "playback code"),
            std::string::npos);
}

CertificateEquilibria sided(int axis, Equilibria verdict, double fx_plus) {
  CertificateEquilibria e;
  e.seed = 16;
  e.step = 11;
  e.axis = axis;
  e.along = 0.005;
  e.verdict = verdict;
  e.force_minus = std::array<double, 3>{-2.0e-3, 0.0, 0.0234};
  e.force_plus = std::array<double, 3>{fx_plus, 0.0, 0.0234};
  return e;
}

// The two-sided solves at a worst step: a jump is named (in the report, its headline and the
// JSON), a ramp is told apart from it.
TEST(CertificateReport, TellsAJumpFromARamp) {
  Certificate c = certificate(0.25, 0.23, 0.05);
  c.equilibria = {sided(0, Equilibria::kTwo, 7.33e-3), sided(1, Equilibria::kOne, -2.0e-3),
                  sided(2, Equilibria::kOne, -2.0e-3)};
  CertificateLocation worst;
  worst.scheme = 1;
  worst.seed = 16;
  worst.step = 11;
  worst.error = 0.25;
  c.worst = {worst};
  CertificateText t = certificate_text(c);
  EXPECT_NE(t.text.find("two-sided solves at seed 16 step 11, the worst of Hermite ("),
            std::string::npos)
      << t.text;
  EXPECT_NE(t.text.find("x: two equilibria, the forces 9.330e-03 N apart"), std::string::npos)
      << t.text;
  EXPECT_NE(t.text.find("y: one equilibrium"), std::string::npos);
  EXPECT_NE(t.text.find("the force jumps here"), std::string::npos);
  EXPECT_NE(t.headline.find("the force jumps at a worst step"), std::string::npos);
  EXPECT_NE(t.json.find("\"verdict\":\"two\""), std::string::npos) << t.json;
  EXPECT_NE(t.json.find("\"difference_newtons\":0.00933"), std::string::npos) << t.json;

  c.equilibria[0] = sided(0, Equilibria::kOne, -2.0e-3);
  t = certificate_text(c);
  EXPECT_EQ(t.text.find("the force jumps"), std::string::npos);
  EXPECT_NE(t.text.find("no jump here"), std::string::npos) << t.text;
  EXPECT_EQ(t.headline.find("jumps"), std::string::npos);

  c.equilibria[1].force_plus.reset();  // Newton failed from +along
  c.equilibria[1].verdict = Equilibria::kEnds;
  t = certificate_text(c);
  EXPECT_NE(t.text.find("y: Newton failed from +along only"), std::string::npos) << t.text;
  EXPECT_NE(t.text.find("the force jumps here"), std::string::npos);
  EXPECT_NE(t.json.find("\"force_plus\":null"), std::string::npos);
}

// What a certificate is measured on: the file's source hash and this build's playback code.
TEST(CertificateReport, CertifiedHashDependsOnTheFileAndTheCode) {
  EXPECT_NE(certified_hash(1).value, 1u);
  EXPECT_NE(certified_hash(1), certified_hash(2));
  EXPECT_EQ(certified_hash(1), certified_hash(1));
  ContentHasher other_code;
  other_code.update(std::int64_t{1});
  other_code.update(static_cast<std::int64_t>(playback_code_id() ^ 1));
  EXPECT_NE(certified_hash(1), other_code.value());
}

}  // namespace
}  // namespace hapstate
