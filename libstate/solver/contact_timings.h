// Collision-detection cost of a contact probe, for benchmarks.
#pragma once

namespace hapstate {

struct ContactTimings {
  double detection = 0;   // seconds spent finding what the sphere touches
  long long queries = 0;  // passes over the candidates (sticking) or the triangles (frictionless)
};

}  // namespace hapstate
