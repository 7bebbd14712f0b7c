// The expansion's progress estimate: how many transitions are left and how long they will take.
// Pure functions of what the expand loop knows (counts from the catalogue, the wall time of its
// batches), so that the model is tested on a measured expansion (tests/statespace/
// expansion_eta_test) without running one.
//
// Why a model and not the run's rate: on a contact scene every wave pushes the sphere deeper,
// and its transitions cost more than the last wave's (the bundled plate, 2 threads: 0.02, 0.08,
// 0.15, 0.22, 0.27, 0.35 thread-seconds per transition in waves 0-5), and check-points reached from
// both sides of a body keep two levels, so the last waves are larger than the unreached
// check-points say. The run's recent rate for a count of unreached check-points promised the
// plate's second half in about 60 % of its time (issue 42).
#pragma once

#include <map>
#include <vector>

namespace hapstate {

// Configurations still to expand after the current wave `wave` (26 transitions each): the open
// configurations of later waves, plus, while workspace check-points are unreached, the
// configurations these need at the levels per check-point seen so far, counted from wave 1 on
// in whole waves as large as the current one (the nearest number of them, at least one). Whole
// waves, because a contact scene's fronts keep their size until the force limit stops them:
// the plate's last wave fills check-points already reached from the other side with second
// levels, which a count of unreached check-points misses; a shrinking front (the outer shells
// of liver-contact) is over-counted by up to one wave near the end (at least one is counted),
// and where probe.max_force ends the expansion before every check-point is reached the count
// is too high. Wave 0 (the zero
// configurations: the rest state, or every free check-point of a contact scene) is no front:
// there the count of unreached check-points alone. Nothing once every check-point is reached.
long long later_configurations(int wave, long long later_open, long long unreached,
                               double per_checkpoint, long long current_wave_configurations);

class ExpansionEta {
 public:
  // Each later wave costs more per transition than the one before by a step: the difference
  // measured between the last two whole waves after wave 0, at least 0 and at most this
  // fraction of the later one's cost. Additive, not a factor: the plate's costs rise by a
  // near-constant 0.06-0.07 thread-s per wave, and a factor compounded over the many waves a
  // large grab grid counts would run away.
  static constexpr double kMaxStep = 0.25;
  // The prediction's weight against a wave's own cost, in transitions of that wave.
  static constexpr double kPriorTransitions = 128;

  // A batch of `decided` transitions of wave `wave` took `seconds` of wall time.
  void record(int wave, long long decided, double seconds);
  // Wave `wave` was not measured from its start (a resumed run's first wave): its cost serves
  // its own rest, not the prediction of later waves or their step.
  void mark_partial(int wave);

  // Seconds left: `current_left` undecided transitions of wave `wave`, then `later`
  // transitions in waves of `wave_size`, each costing the step more per transition than the
  // one before. The current wave's cost blends the earlier waves' prediction (the latest whole
  // one's cost, one step more) with this wave's own cost so far (weight n / (n + 128) after n
  // transitions). Negative when nothing has been measured yet (no estimate).
  double seconds_left(int wave, long long current_left, long long later, long long wave_size) const;

  // Seconds per transition measured in `wave` (negative if none).
  double cost(int wave) const;
  // The per-wave step of the cost used for the waves after `wave`'s predecessors.
  double step(int wave) const;

 private:
  struct Work {
    long long decided = 0;
    double seconds = 0;
    bool partial = false;
  };
  // The costs of the whole waves before `wave`, oldest first.
  std::vector<double> earlier_costs(int wave) const;
  std::map<int, Work> waves_;
};

}  // namespace hapstate
