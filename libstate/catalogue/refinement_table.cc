// Table refinement: the solved points of refined cells (schema 6).
#include "catalogue/catalogue_impl.hpp"
#include "util/error.h"

#include <algorithm>

namespace hapstate {
namespace {

#define HAPSTATE_REFINEMENT_COLUMNS                                                           \
  "cell, point, outcome, fx, fy, fz, k0, k1, k2, k3, k4, k5, k6, k7, k8, newton_iterations, " \
  "wall_ms, failure_reason"

constexpr const char* kInsert = "INSERT INTO refinement (" HAPSTATE_REFINEMENT_COLUMNS
                                ") VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)";
constexpr const char* kReadAll =
    "SELECT " HAPSTATE_REFINEMENT_COLUMNS " FROM refinement ORDER BY cell, point";
// The cells with points of one depth (the bounds: records.h, kEighthFirstPoint and after).
constexpr const char* kCells[3] = {
    "SELECT DISTINCT cell FROM refinement WHERE point < 125 ORDER BY cell",
    "SELECT DISTINCT cell FROM refinement WHERE point >= 125 AND point < 854 ORDER BY cell",
    "SELECT DISTINCT cell FROM refinement WHERE point >= 854 ORDER BY cell"};
constexpr const char* kCount = "SELECT count(*) FROM refinement";

#undef HAPSTATE_REFINEMENT_COLUMNS

}  // namespace

void Catalogue::insert_refinement_points(const std::vector<RefinementPoint>& points) {
  catalogue_detail::Savepoint savepoint(*impl_->db);
  for (const RefinementPoint& p : points) {
    catalogue_detail::StatementUse s(impl_->statement(kInsert));
    s->bind(1, p.cell.value());
    s->bind(2, p.point);
    s->bind(3, p.reached ? 0 : 2);
    for (int k = 0; k < 3; ++k) {
      if (p.reached) {
        s->bind(4 + k, p.force[k]);
      } else {
        s->bind_null(4 + k);
      }
    }
    for (int k = 0; k < 9; ++k) {
      if (p.reached) {
        s->bind(7 + k, p.stiffness[k]);
      } else {
        s->bind_null(7 + k);
      }
    }
    s->bind(16, p.newton_iterations);
    s->bind(17, p.wall_ms);
    s->bind(18, p.failure_reason);
    s->run();
  }
  savepoint.release();
}

std::vector<RefinementPoint> Catalogue::read_all_refinement_points() {
  using catalogue_detail::ranged_column;
  catalogue_detail::StatementUse s(impl_->statement(kReadAll));
  std::vector<RefinementPoint> out;
  while (s->step()) {
    RefinementPoint p;
    p.cell = ConfigId(s->column_int(0));
    p.point = ranged_column(*s, 1, 0, kLastRefinementPoint, impl_->label(), "refinement.point");
    p.reached = ranged_column(*s, 2, 0, 2, impl_->label(), "refinement.outcome") == 0;
    if (p.reached) {
      for (int k = 0; k < 3; ++k) p.force[k] = s->column_double(3 + k);
      for (int k = 0; k < 9; ++k) p.stiffness[k] = s->column_double(6 + k);
    }
    p.newton_iterations = static_cast<int>(s->column_int(15));
    p.wall_ms = s->column_double(16);
    p.failure_reason = s->column_text(17);
    out.push_back(std::move(p));
  }
  return out;
}

std::set<ConfigId> Catalogue::refined_cells(int depth) {
  catalogue_detail::StatementUse s(impl_->statement(kCells[std::clamp(depth, 1, 3) - 1]));
  std::set<ConfigId> out;
  while (s->step()) out.insert(ConfigId(s->column_int(0)));
  return out;
}

std::int64_t Catalogue::num_refinement_points() {
  catalogue_detail::StatementUse s(impl_->statement(kCount));
  s->step();
  return s->column_int(0);
}

}  // namespace hapstate
