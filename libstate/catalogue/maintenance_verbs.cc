// Verbs of the compaction stage: blob references, transition rewriting, VACUUM.
#include "catalogue/catalogue_impl.hpp"
#include "util/error.h"

#include <stdexcept>

namespace hapstate {
namespace {

constexpr const char* kUpdateBlob =
    "UPDATE configuration SET blob_segment = ?, blob_name = ? WHERE id = ?";
constexpr const char* kUpdateMidpointBlob =
    "UPDATE transition SET midpoint_blob_segment = ?, midpoint_blob_name = ? "
    "WHERE source = ? AND direction = ?";
constexpr const char* kRetarget = "UPDATE transition SET target = ? WHERE target = ?";
constexpr const char* kMove =
    "UPDATE transition SET source = ?1 WHERE source = ?2 AND direction NOT IN "
    "(SELECT direction FROM transition WHERE source = ?1)";

}  // namespace

void Catalogue::update_configuration_blob(ConfigId id, const std::optional<BlobRef>& blob) {
  catalogue_detail::StatementUse s(impl_->statement(kUpdateBlob));
  if (blob) {
    s->bind(1, blob->segment.value);
    s->bind(2, blob->name);
  } else {
    s->bind_null(1);
    s->bind_null(2);
  }
  s->bind(3, id.value());
  s->run();
  if (sqlite3_changes(impl_->db->get()) != 1) {
    throw InputError(impl_->label() + ": no configuration with id " + std::to_string(id.value()));
  }
}

bool Catalogue::update_transition_midpoint_blob(ConfigId source, Direction direction,
                                                const BlobRef& blob) {
  catalogue_detail::StatementUse s(impl_->statement(kUpdateMidpointBlob));
  s->bind(1, blob.segment.value);
  s->bind(2, blob.name);
  s->bind(3, source.value());
  s->bind(4, direction.index());
  s->run();
  return sqlite3_changes(impl_->db->get()) == 1;
}

std::int64_t Catalogue::retarget_transitions(ConfigId from, ConfigId to) {
  catalogue_detail::StatementUse s(impl_->statement(kRetarget));
  s->bind(1, to.value());
  s->bind(2, from.value());
  s->run();
  return sqlite3_changes64(impl_->db->get());
}

std::int64_t Catalogue::move_transitions(ConfigId from, ConfigId to) {
  catalogue_detail::StatementUse s(impl_->statement(kMove));
  s->bind(1, to.value());
  s->bind(2, from.value());
  s->run();
  return sqlite3_changes64(impl_->db->get());
}

void Catalogue::vacuum() {
  if (impl_->in_transaction) throw std::logic_error("Catalogue::vacuum inside a transaction");
  impl_->statements.clear();  // finalised: VACUUM wants no pending statement
  impl_->db->exec("VACUUM");
  impl_->db->query_text("PRAGMA wal_checkpoint(TRUNCATE)");
}

}  // namespace hapstate
