// Whether two configurations at one check-point are the same level (DESIGN.md section 3):
// max(||u - u'||_inf / u_tol, ||h - h'||_2 / h_tol) <= 1, with the scene's level tolerances.
#pragma once

#include "catalogue/records.h"
#include "scene/scene.h"

#include <cstddef>
#include <span>
#include <vector>

namespace hapstate {

class BlobStore;

// The distance in units of the tolerances: <= 1 means "same level". Vectors of different
// lengths are never the same level (returns +infinity). Preconditions: tolerances > 0.
double level_distance(std::span<const double> u, std::span<const double> h,
                      std::span<const double> u_other, std::span<const double> h_other,
                      const LevelTolerances& tolerances);

// Cheap necessary condition, from the catalogue rows only: the felt force is the sum of the
// reactions h over the probe nodes (up to sign), so ||F - F'||_2 <= sqrt(len(h)) ||h - h'||_2.
// Returns true when the forces alone prove the two are different levels (no blob read needed).
// `h_length` is the number of reaction values (BlobStore::size_of, no data read).
bool forces_prove_distinct(const Configuration& a, const Configuration& b, std::size_t h_length,
                           const LevelTolerances& tolerances);

// Cheap necessary condition from the stored summaries: the expand stage's summary is u at a
// fixed set of sample nodes (statespace LevelSketch), so ||s - s'||_inf <= ||u - u'||_inf.
// Returns true when the summaries alone prove two different levels. Summaries of different
// lengths (or empty) prove nothing.
bool summaries_prove_distinct(const Configuration& a, const Configuration& b,
                              const LevelTolerances& tolerances);

// Reads the vectors u and h of `c` ("<blob>/u", "<blob>/h"). A configuration without a blob is
// the trivial zero state: empty vectors, compared as zeros of the other's length.
struct LevelVectors {
  std::vector<double> u, h;
};
LevelVectors read_level_vectors(const BlobStore& blobs, const Configuration& c);

// level_distance for two read configurations, with the zero-state rule above.
double level_distance(const LevelVectors& a, const LevelVectors& b,
                      const LevelTolerances& tolerances);

}  // namespace hapstate
