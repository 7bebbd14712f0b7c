// The accuracy bounds of the paper's prototype (Peterlik & Matyska 2007: force error below 4 %,
// deformation error below 14 %), against which hapstate-eval and the certificate judge a state.
#pragma once

namespace hapstate {

inline constexpr double kPaperForceBound = 0.04;
inline constexpr double kPaperDeformationBound = 0.14;

}  // namespace hapstate
