// Which degrees of freedom are free, fixed at zero, or prescribed by the probe.
// DOF index = 3 * node + component (component 0 = x, 1 = y, 2 = z).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace hapstate {

enum class DofRole : std::uint8_t { kFree = 0, kFixed = 1, kProbe = 2 };

struct Constraints {
  std::vector<DofRole> role;     // size 3 * num_nodes
  std::vector<int> probe_nodes;  // grabbed nodes; they translate rigidly with the probe
  std::array<bool, 3> probe_components{true, true, true};  // components that follow the probe
};

}  // namespace hapstate
