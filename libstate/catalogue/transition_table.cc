// Table transition.
#include "catalogue/catalogue_impl.hpp"
#include "util/error.h"

namespace hapstate {
namespace {

#define HAPSTATE_TRANSITION_COLUMNS                                                   \
  "source, direction, outcome, target, substeps, newton_iterations, final_residual, " \
  "wall_ms, failure_reason, factorisations, midpoint_fx, midpoint_fy, midpoint_fz, "  \
  "midpoint_k0, midpoint_k1, midpoint_k2, midpoint_k3, midpoint_k4, midpoint_k5, "    \
  "midpoint_k6, midpoint_k7, midpoint_k8, midpoint_blob_segment, midpoint_blob_name"

constexpr const char* kInsert =
    "INSERT INTO transition (" HAPSTATE_TRANSITION_COLUMNS
    ") VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)";
constexpr const char* kRead =
    "SELECT " HAPSTATE_TRANSITION_COLUMNS " FROM transition WHERE source = ? AND direction = ?";
constexpr const char* kOfSource =
    "SELECT " HAPSTATE_TRANSITION_COLUMNS " FROM transition WHERE source = ? ORDER BY direction";
constexpr const char* kReadAll =
    "SELECT " HAPSTATE_TRANSITION_COLUMNS " FROM transition ORDER BY source, direction";
constexpr const char* kCount = "SELECT count(*) FROM transition";
constexpr const char* kCountFailed = "SELECT count(*) FROM transition WHERE outcome = 2";
constexpr const char* kDelete = "DELETE FROM transition WHERE source = ? AND direction = ?";

#undef HAPSTATE_TRANSITION_COLUMNS

Transition row_to_transition(const catalogue_detail::Statement& s, const std::string& label) {
  using catalogue_detail::ranged_column;
  Transition t;
  t.source = ConfigId(s.column_int(0));
  t.direction =
      Direction(ranged_column(s, 1, 0, Direction::kCount - 1, label, "transition.direction"));
  t.outcome =
      static_cast<TransitionOutcome>(ranged_column(s, 2, 0, 2, label, "transition.outcome"));
  if (!s.is_null(3)) t.target = ConfigId(s.column_int(3));
  t.substeps = static_cast<int>(s.column_int(4));
  t.newton_iterations = static_cast<int>(s.column_int(5));
  t.final_residual = s.column_double(6);
  t.wall_ms = s.column_double(7);
  t.failure_reason = s.column_text(8);
  t.factorisations = static_cast<int>(s.column_int(9));
  if (!s.is_null(10) && !s.is_null(11) && !s.is_null(12))
    t.midpoint_force =
        std::array<double, 3>{s.column_double(10), s.column_double(11), s.column_double(12)};
  bool stiffness = true;
  for (int k = 0; k < 9; ++k) stiffness = stiffness && !s.is_null(13 + k);
  if (stiffness) {
    std::array<double, 9> k{};
    for (int i = 0; i < 9; ++i) k[i] = s.column_double(13 + i);
    t.midpoint_stiffness = k;
  }
  if (!s.is_null(22) && !s.is_null(23))
    t.midpoint_blob = BlobRef{SegmentId{s.column_int(22)}, s.column_text(23)};
  return t;
}

}  // namespace

void Catalogue::insert_transition(const Transition& t) {
  catalogue_detail::StatementUse s(impl_->statement(kInsert));
  s->bind(1, t.source.value());
  s->bind(2, t.direction.index());
  s->bind(3, static_cast<int>(t.outcome));
  if (t.target.valid()) {
    s->bind(4, t.target.value());
  } else {
    s->bind_null(4);
  }
  s->bind(5, t.substeps);
  s->bind(6, t.newton_iterations);
  s->bind(7, t.final_residual);
  s->bind(8, t.wall_ms);
  s->bind(9, t.failure_reason);
  s->bind(10, t.factorisations);
  for (int k = 0; k < 3; ++k) {
    if (t.midpoint_force) {
      s->bind(11 + k, (*t.midpoint_force)[k]);
    } else {
      s->bind_null(11 + k);
    }
  }
  for (int k = 0; k < 9; ++k) {
    if (t.midpoint_stiffness) {
      s->bind(14 + k, (*t.midpoint_stiffness)[k]);
    } else {
      s->bind_null(14 + k);
    }
  }
  if (t.midpoint_blob) {
    s->bind(23, t.midpoint_blob->segment.value);
    s->bind(24, t.midpoint_blob->name);
  } else {
    s->bind_null(23);
    s->bind_null(24);
  }
  s->run();
}

std::optional<Transition> Catalogue::read_transition(ConfigId source, Direction direction) {
  catalogue_detail::StatementUse s(impl_->statement(kRead));
  s->bind(1, source.value());
  s->bind(2, direction.index());
  if (!s->step()) return std::nullopt;
  return row_to_transition(*s, impl_->label());
}

std::vector<Transition> Catalogue::transitions_of(ConfigId source) {
  catalogue_detail::StatementUse s(impl_->statement(kOfSource));
  s->bind(1, source.value());
  std::vector<Transition> out;
  while (s->step()) out.push_back(row_to_transition(*s, impl_->label()));
  return out;
}

std::vector<Transition> Catalogue::read_all_transitions() {
  catalogue_detail::StatementUse s(impl_->statement(kReadAll));
  std::vector<Transition> out;
  while (s->step()) out.push_back(row_to_transition(*s, impl_->label()));
  return out;
}

std::int64_t Catalogue::num_transitions() {
  catalogue_detail::StatementUse s(impl_->statement(kCount));
  s->step();
  return s->column_int(0);
}

std::int64_t Catalogue::num_failed_transitions() {
  catalogue_detail::StatementUse s(impl_->statement(kCountFailed));
  s->step();
  return s->column_int(0);
}

bool Catalogue::delete_transition(ConfigId source, Direction direction) {
  catalogue_detail::StatementUse s(impl_->statement(kDelete));
  s->bind(1, source.value());
  s->bind(2, direction.index());
  s->run();
  return sqlite3_changes(impl_->db->get()) == 1;
}

}  // namespace hapstate
