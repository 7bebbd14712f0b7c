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
