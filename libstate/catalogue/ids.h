// Strong id types of the catalogue: a ConfigId is not a CheckpointId is not a level number,
// so mixing them up does not compile. Each default-constructs to its kInvalid sentinel.
#pragma once

#include <compare>
#include <cstdint>
#include <functional>

namespace hapstate {

// An integer id tagged with the kind of thing it names. Rows ids are >= 0 when valid
// (SQLite rowids start at 1; level numbers at 0); -1 is invalid.
template <class Tag>
class StrongId {
 public:
  using Rep = std::int64_t;
  constexpr StrongId() = default;
  constexpr explicit StrongId(Rep value) : value_(value) {}
  constexpr Rep value() const { return value_; }
  constexpr bool valid() const { return value_ >= 0; }
  friend constexpr auto operator<=>(StrongId, StrongId) = default;

 private:
  Rep value_ = -1;
};

using ConfigId = StrongId<struct ConfigIdTag>;          // row of table configuration
using CheckpointId = StrongId<struct CheckpointIdTag>;  // row of table checkpoint
using StageRunId = StrongId<struct StageRunIdTag>;      // row of table stage_run
using Level = StrongId<struct LevelTag>;                // 0, 1, ... per check-point

inline constexpr ConfigId kInvalidConfigId{};
inline constexpr CheckpointId kInvalidCheckpointId{};
inline constexpr StageRunId kInvalidStageRunId{};
inline constexpr Level kInvalidLevel{};

}  // namespace hapstate

template <class Tag>
struct std::hash<hapstate::StrongId<Tag>> {
  std::size_t operator()(hapstate::StrongId<Tag> id) const noexcept {
    return std::hash<std::int64_t>()(id.value());
  }
};
