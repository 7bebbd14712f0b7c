// The public interface of hapstate::state for other programs: the precise path solver on a
// scene file (docs/scene.md). The playback runtime a haptic loop links is hapstate/playback.h.
//
//   hapstate::SceneSolver solver("organ.toml");          // reads the scene and its mesh
//   hapstate::MoveOutcome m = solver.move_to({x, y, z}); // probe position, mesh units
//   if (m.ok) use(solver.force_felt());                  // N
//
// Errors: a bad scene or mesh throws hapstate::InputError naming the file, the place and what is
// wrong; an I/O failure throws hapstate::EnvironmentError (hapstate/error.h). A move that does
// not converge is not an exception: the outcome says why, and the state stays where it was.
// Not thread-safe: one SceneSolver per thread (several may run at once).
#pragma once

#include "hapstate/error.h"

#include <Eigen/Core>

#include <memory>
#include <string>

namespace hapstate {

// One probe move of the precise solver.
struct MoveOutcome {
  bool ok = true;
  std::string failure;  // "" if ok, else the failure's name (e.g. "line_search")
  std::string reason;   // "" if ok, else what happened, in words
  int iterations = 0;   // Newton iterations
  int substeps = 0;     // accepted sub-steps
  int cutbacks = 0;     // sub-step halvings
  double residual = 0;  // final free-DOF residual [N]
  double wall_ms = 0;
};

class SceneSolver {
 public:
  // Reads and validates the scene file and the mesh it names; the body starts at rest.
  explicit SceneSolver(const std::string& scene_file);
  ~SceneSolver();
  SceneSolver(SceneSolver&&) noexcept;
  SceneSolver& operator=(SceneSolver&&) noexcept;

  int num_nodes() const;
  double unit() const;                 // metres per mesh unit
  Eigen::Vector3d probe_rest() const;  // probe position at rest, mesh units
  bool contact() const;                // true for a contact (sphere) probe

  // Moves the probe to `probe_position` (absolute, mesh units) from the current state.
  MoveOutcome move_to(const Eigen::Vector3d& probe_position);
  // Back to the rest state.
  void reset();

  Eigen::Vector3d force_felt() const;      // N, the force the user feels
  Eigen::Matrix3d haptic_stiffness();      // d force_felt / d probe position, N per mesh unit
  Eigen::Matrix3Xd displacements() const;  // per node, mesh units

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hapstate
