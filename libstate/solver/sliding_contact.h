// Frictionless contact of a rigid sphere with the deformed surface triangles (docs/contact.md),
// by an augmented Lagrangian on the gap of every surface triangle,
//   g_T = d_T(x, c) - r,   d_T = distance from the centre c to triangle T,
// which must stay >= 0 (no surface point inside the sphere). With a multiplier lambda_T >= 0 per
// triangle and a penalty k, the contact adds to the potential energy
//   Psi = sum_T [ max(0, lambda_T - k g_T)^2 - lambda_T^2 ] / (2k),
// whose force on the body, -lambda^_T grad_x d_T with lambda^_T = max(0, lambda_T - k g_T) >= 0,
// acts along the sphere's normal at the closest point (no tangential part, no adhesion), spread
// on the triangle's corners by the closest point's barycentric weights. After each Newton
// solve the multipliers are updated (lambda_T <- lambda^_T) until the gaps close to
// SolverOptions::gap_tolerance.
// The solver works in metres: positions, u and the centre are in metres here, forces in N.
// Not thread-safe: one per PathSolver.
#pragma once

#include "fem/assembler.h"
#include "mesh/mesh.h"
#include "solver/triangle_distance.h"

#include <Eigen/Core>

#include <array>
#include <vector>

namespace hapstate {

class SlidingContact {
 public:
  // `positions_m`: reference node positions [m]; `radius_m` [m]; `penalty` k [N/m] (> 0);
  // the surface triangles of `mesh` are the contact faces. Every triangle's node pairs must be
  // in `pattern` (they are: a surface triangle is a face of a tet).
  SlidingContact(const Eigen::Matrix3Xd& positions_m, const Triangles& surface, double radius_m,
                 double penalty, const SymmetricPattern& pattern);

  double radius() const { return radius_; }
  // The penalty k = penalty_scale() x the constructor's base_penalty() (the solver stiffens it
  // when the multiplier updates contract too slowly, and resets it for every sub-step).
  double penalty() const { return base_penalty_ * penalty_scale_; }
  double base_penalty() const { return base_penalty_; }
  double penalty_scale() const { return penalty_scale_; }
  void set_penalty_scale(double scale) { penalty_scale_ = scale; }
  void reset_multipliers() { std::fill(lambda_.begin(), lambda_.end(), 0.0); }
  const std::vector<double>& multipliers() const { return lambda_; }
  void set_multipliers(const std::vector<double>& m) { lambda_ = m; }
  // The non-zero multipliers as pairs (triangle index, lambda [N]), ascending by triangle: what a
  // stored configuration keeps to warm-start a later move.
  std::vector<double> sparse_multipliers() const;
  // Sets them from such pairs (all others zero); returns false (nothing changed) if a pair is
  // not (an index of a surface triangle, a finite lambda >= 0).
  bool set_sparse_multipliers(const std::vector<double>& pairs);

  // Adds dPsi/du to f [N]; returns Psi, the contact energy with the multipliers held [J].
  double add_force(const Eigen::VectorXd& u_m, const Eigen::Vector3d& centre_m,
                   Eigen::VectorXd* f) const;
  // Adds d2Psi/du2 to the upper-triangle values `k_values` (pattern order). `psd_only`: only the
  // positive semi-definite part k grad d grad d^T (the solver's fallback). `hessian_penalty`
  // (> 0) replaces k in that part: the haptic stiffness uses a stiff value so that the active
  // gaps act as the exact constraints they converge to.
  void add_tangent(const Eigen::VectorXd& u_m, const Eigen::Vector3d& centre_m,
                   std::vector<double>* k_values, bool psd_only = false,
                   double hessian_penalty = 0) const;
  // The mixed derivatives d2Psi/du dc (3 columns, num_dofs rows) and d2Psi/dc2, with the same
  // `hessian_penalty` convention.
  void add_coupling(const Eigen::VectorXd& u_m, const Eigen::Vector3d& centre_m,
                    Eigen::Matrix<double, Eigen::Dynamic, 3>* k_uc, Eigen::Matrix3d* k_cc,
                    double hessian_penalty = 0) const;
  // The force the body exerts on the sphere [N], -dPsi/dc = sum_T lambda^_T n_T (the felt force).
  Eigen::Vector3d force_on_probe(const Eigen::VectorXd& u_m, const Eigen::Vector3d& centre_m) const;
  // The multiplier update lambda_T <- lambda^_T. Returns the largest change divided by k [m]: the
  // largest gap violation of the state before the update (penetration of an active triangle,
  // or the gap of a triangle that still held a multiplier).
  double update_multipliers(const Eigen::VectorXd& u_m, const Eigen::Vector3d& centre_m);
  // The same measure without changing the multipliers.
  double violation(const Eigen::VectorXd& u_m, const Eigen::Vector3d& centre_m) const;
  // Whether any triangle carries a contact force (lambda^ > 0).
  bool any_active(const Eigen::VectorXd& u_m, const Eigen::Vector3d& centre_m) const;
  // The nodes of the triangles carrying a contact force, ascending.
  std::vector<int> touched_nodes(const Eigen::VectorXd& u_m, const Eigen::Vector3d& centre_m) const;
  // Collision-detection cost so far: seconds and queries (one per pass over the triangles).
  double detection_seconds() const { return detection_seconds_; }
  long long queries() const { return queries_; }

 private:
  struct Active {
    int triangle;
    double lambda_hat;
    std::array<Eigen::Vector3d, 3> x;
  };
  Mat12d term_hessian(const Active& a, const Eigen::Vector3d& centre_m, double k,
                      bool psd_only) const;
  // lambda^ of every triangle at (u, c), and the largest |lambda^ - lambda| / k [m].
  std::vector<double> updated(const Eigen::VectorXd& u_m, const Eigen::Vector3d& centre_m,
                              double* worst_change) const;
  // The triangles whose lambda^ > 0 at (u, c) (a scan with a bounding-box cull).
  const std::vector<Active>& active(const Eigen::VectorXd& u_m,
                                    const Eigen::Vector3d& centre_m) const;

  Eigen::Matrix3Xd reference_;
  Triangles triangles_;
  double radius_, base_penalty_;
  double penalty_scale_ = 1.0;
  std::vector<std::array<int, 45>> scatter_;  // per triangle: upper 9x9 entries in the pattern
  std::vector<double> lambda_;
  mutable std::vector<Active> active_;
  mutable double detection_seconds_ = 0;
  mutable long long queries_ = 0;
};

}  // namespace hapstate
