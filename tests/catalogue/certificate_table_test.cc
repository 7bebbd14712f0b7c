// Tables certificate_path, certificate_step and certificate_equilibria (catalogue.h): what is
// stored reads back the same (a failed approach as no force), and a stale certificate's
// two-sided solves go with it. Truth: the rows written.
#include "catalogue/catalogue.h"

#include <gtest/gtest.h>

#include <vector>

namespace hapstate {
namespace {

CertificatePath path(int seed, const ContentHash& hash) {
  CertificatePath p;
  p.seed = seed;
  p.playback_hash = hash;
  p.steps = 2;
  p.max_force = 0.02;
  p.wall_ms = 5;
  for (int s = 1; s <= 2; ++s) {
    CertificateStep r;
    r.step = s;
    r.probe = {0.1 * s, 0.2, -0.3};
    r.solved = true;
    r.force = 0.01 * s;
    r.error = {1e-4, 2e-4 * s};
    r.deformation = {0.01, 0.02};
    p.rows.push_back(r);
  }
  return p;
}

std::vector<CertificateEquilibria> three_axes(int seed, int step, const ContentHash& hash) {
  std::vector<CertificateEquilibria> rows;
  for (int a = 0; a < 3; ++a) {
    CertificateEquilibria e;
    e.seed = seed;
    e.step = step;
    e.axis = a;
    e.along = 0.005;
    e.verdict = a == 0 ? Equilibria::kTwo : (a == 1 ? Equilibria::kEnds : Equilibria::kOne);
    e.force_minus = std::array<double, 3>{-2.0e-3, -1.2e-3, 23.4e-3};
    if (a != 1) e.force_plus = std::array<double, 3>{7.33e-3, -3.23e-3, 22.17e-3};
    e.playback_hash = hash;
    e.wall_ms = 100 + a;
    rows.push_back(e);
  }
  return rows;
}

TEST(CertificateTable, EquilibriaReadBackAndGoWithAStaleCertificate) {
  Catalogue cat(":memory:", OpenMode::kCreate);
  const ContentHash hash{0x1234}, other{0x5678};
  cat.insert_certificate_path(path(1, hash));
  cat.insert_certificate_path(path(2, hash));
  const auto rows = three_axes(2, 2, hash);
  cat.insert_certificate_equilibria(rows);
  EXPECT_EQ(cat.read_all_certificate_equilibria(), rows);
  EXPECT_FALSE(cat.read_all_certificate_equilibria()[1].force_plus.has_value());
  EXPECT_ANY_THROW(cat.insert_certificate_equilibria({rows[0]}));  // (seed, step, axis) exists

  // Solves measured on another playback file than their path's: stale alone, the path stays.
  cat.insert_certificate_equilibria(three_axes(1, 2, other));
  EXPECT_EQ(cat.delete_stale_certificate(hash, 2, 2), 0);
  EXPECT_EQ(cat.read_all_certificate_equilibria(), rows);
  EXPECT_EQ(cat.read_all_certificate_paths().size(), 2u);
  // Fewer paths: seed 2 and its solves are stale.
  EXPECT_EQ(cat.delete_stale_certificate(hash, 2, 1), 1);
  EXPECT_TRUE(cat.read_all_certificate_equilibria().empty());
  // Another playback file: all of it.
  cat.insert_certificate_equilibria(three_axes(1, 1, hash));
  EXPECT_EQ(cat.read_all_certificate_equilibria().size(), 3u);
  EXPECT_EQ(cat.delete_stale_certificate(other, 2, 1), 1);
  EXPECT_TRUE(cat.read_all_certificate_equilibria().empty());
  EXPECT_TRUE(cat.read_all_certificate_paths().empty());
}

}  // namespace
}  // namespace hapstate
