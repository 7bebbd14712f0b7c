// Table checkpoint.
#include "catalogue/catalogue_impl.hpp"
#include "util/error.h"

namespace hapstate {
namespace {

constexpr const char* kInsert =
    "INSERT INTO checkpoint (id, i, j, k, x, y, z, classification) VALUES (?, ?, ?, ?, ?, ?, ?, ?)";
constexpr const char* kRead =
    "SELECT id, i, j, k, x, y, z, classification FROM checkpoint WHERE id = ?";
constexpr const char* kFind =
    "SELECT id, i, j, k, x, y, z, classification FROM checkpoint WHERE i = ? AND j = ? AND k = ?";
constexpr const char* kReadAll =
    "SELECT id, i, j, k, x, y, z, classification FROM checkpoint ORDER BY id";
constexpr const char* kCount = "SELECT count(*) FROM checkpoint";
constexpr const char* kExists = "SELECT 1 FROM checkpoint WHERE id = ?";

Checkpoint row_to_checkpoint(const catalogue_detail::Statement& s, const std::string& label) {
  Checkpoint c;
  c.id = CheckpointId(s.column_int(0));
  for (int a = 0; a < 3; ++a) {
    c.ijk[a] = static_cast<int>(s.column_int(1 + a));
    c.position[a] = s.column_double(4 + a);
  }
  c.classification = static_cast<CheckpointClass>(
      catalogue_detail::ranged_column(s, 7, 0, 4, label, "checkpoint.classification"));
  return c;
}

}  // namespace

CheckpointId Catalogue::insert_checkpoint(const Checkpoint& checkpoint) {
  catalogue_detail::StatementUse s(impl_->statement(kInsert));
  if (checkpoint.id.valid()) {
    s->bind(1, checkpoint.id.value());
  } else {
    s->bind_null(1);
  }
  for (int a = 0; a < 3; ++a) {
    s->bind(2 + a, checkpoint.ijk[a]);
    s->bind(5 + a, checkpoint.position[a]);
  }
  s->bind(8, static_cast<int>(checkpoint.classification));
  s->run();
  return CheckpointId(sqlite3_last_insert_rowid(impl_->db->get()));
}

Checkpoint Catalogue::read_checkpoint(CheckpointId id) {
  catalogue_detail::StatementUse s(impl_->statement(kRead));
  s->bind(1, id.value());
  if (!s->step()) {
    throw InputError(impl_->label() + ": no checkpoint with id " + std::to_string(id.value()));
  }
  return row_to_checkpoint(*s, impl_->label());
}

std::optional<Checkpoint> Catalogue::find_checkpoint(const std::array<int, 3>& ijk) {
  catalogue_detail::StatementUse s(impl_->statement(kFind));
  for (int a = 0; a < 3; ++a) s->bind(1 + a, ijk[a]);
  if (!s->step()) return std::nullopt;
  return row_to_checkpoint(*s, impl_->label());
}

std::vector<Checkpoint> Catalogue::read_all_checkpoints() {
  catalogue_detail::StatementUse s(impl_->statement(kReadAll));
  std::vector<Checkpoint> all;
  while (s->step()) all.push_back(row_to_checkpoint(*s, impl_->label()));
  return all;
}

std::int64_t Catalogue::num_checkpoints() {
  catalogue_detail::StatementUse s(impl_->statement(kCount));
  s->step();
  return s->column_int(0);
}

bool Catalogue::exists_checkpoint(CheckpointId id) {
  catalogue_detail::StatementUse s(impl_->statement(kExists));
  s->bind(1, id.value());
  return s->step();
}

}  // namespace hapstate
