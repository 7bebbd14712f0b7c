// Table configuration.
#include "catalogue/catalogue_impl.hpp"
#include "util/error.h"

namespace hapstate {
namespace {

#define HAPSTATE_CONFIG_COLUMNS                                                            \
  "id, checkpoint, level, wave, force_x, force_y, force_z, k_xx, k_xy, k_xz, k_yx, k_yy, " \
  "k_yz, k_zx, k_zy, k_zz, expandable, status, blob_segment, blob_name, summary"

constexpr const char* kInsert = "INSERT INTO configuration (" HAPSTATE_CONFIG_COLUMNS
                                ") VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, "
                                "?, ?, ?)";
constexpr const char* kRead = "SELECT " HAPSTATE_CONFIG_COLUMNS " FROM configuration WHERE id = ?";
constexpr const char* kAtCheckpoint =
    "SELECT " HAPSTATE_CONFIG_COLUMNS " FROM configuration WHERE checkpoint = ? ORDER BY level";
constexpr const char* kFrontier = "SELECT " HAPSTATE_CONFIG_COLUMNS
                                  " FROM configuration WHERE wave = ? AND status = 0 AND "
                                  "expandable = 1 ORDER BY id";
constexpr const char* kReadAll =
    "SELECT " HAPSTATE_CONFIG_COLUMNS " FROM configuration ORDER BY id";
constexpr const char* kCount = "SELECT count(*) FROM configuration";
constexpr const char* kExists = "SELECT 1 FROM configuration WHERE id = ?";
constexpr const char* kUpdateStatus = "UPDATE configuration SET status = ? WHERE id = ?";
constexpr const char* kUpdateExpandable = "UPDATE configuration SET expandable = ? WHERE id = ?";
constexpr const char* kMaxWave = "SELECT max(wave) FROM configuration";
constexpr const char* kNextLevel =
    "SELECT coalesce(max(level) + 1, 0) FROM configuration WHERE checkpoint = ?";
constexpr const char* kMaxId = "SELECT max(id) FROM configuration";
constexpr const char* kSegments =
    "SELECT blob_segment FROM configuration WHERE blob_segment IS NOT NULL UNION "
    "SELECT midpoint_blob_segment FROM transition WHERE midpoint_blob_segment IS NOT NULL";

#undef HAPSTATE_CONFIG_COLUMNS

Configuration row_to_configuration(const catalogue_detail::Statement& s, const std::string& label) {
  Configuration c;
  c.id = ConfigId(s.column_int(0));
  c.checkpoint = CheckpointId(s.column_int(1));
  c.level = Level(s.column_int(2));
  c.wave = static_cast<int>(s.column_int(3));
  for (int a = 0; a < 3; ++a) c.force[a] = s.column_double(4 + a);
  for (int a = 0; a < 9; ++a) c.stiffness[a] = s.column_double(7 + a);
  c.expandable = s.column_int(16) != 0;
  c.status = static_cast<ConfigStatus>(
      catalogue_detail::ranged_column(s, 17, 0, 2, label, "configuration.status"));
  if (!s.is_null(18)) c.blob = BlobRef{SegmentId{s.column_int(18)}, s.column_text(19)};
  c.summary = catalogue_detail::unpack_doubles(
      s.column_blob(20), label + ": configuration " + std::to_string(c.id.value()) + " summary");
  return c;
}

}  // namespace

ConfigId Catalogue::insert_configuration(const Configuration& c) {
  catalogue_detail::StatementUse s(impl_->statement(kInsert));
  if (c.id.valid()) {
    s->bind(1, c.id.value());
  } else {
    s->bind_null(1);
  }
  s->bind(2, c.checkpoint.value());
  s->bind(3, c.level.value());
  s->bind(4, c.wave);
  for (int a = 0; a < 3; ++a) s->bind(5 + a, c.force[a]);
  for (int a = 0; a < 9; ++a) s->bind(8 + a, c.stiffness[a]);
  s->bind(17, c.expandable ? 1 : 0);
  s->bind(18, static_cast<int>(c.status));
  if (c.blob) {
    s->bind(19, c.blob->segment.value);
    s->bind(20, c.blob->name);
  } else {
    s->bind_null(19);
    s->bind_null(20);
  }
  s->bind_blob(21, catalogue_detail::pack_doubles(c.summary));
  s->run();
  return ConfigId(sqlite3_last_insert_rowid(impl_->db->get()));
}

Configuration Catalogue::read_configuration(ConfigId id) {
  catalogue_detail::StatementUse s(impl_->statement(kRead));
  s->bind(1, id.value());
  if (!s->step()) {
    throw InputError(impl_->label() + ": no configuration with id " + std::to_string(id.value()));
  }
  return row_to_configuration(*s, impl_->label());
}

std::vector<Configuration> Catalogue::configurations_at(CheckpointId checkpoint) {
  catalogue_detail::StatementUse s(impl_->statement(kAtCheckpoint));
  s->bind(1, checkpoint.value());
  std::vector<Configuration> out;
  while (s->step()) out.push_back(row_to_configuration(*s, impl_->label()));
  return out;
}

std::vector<Configuration> Catalogue::frontier(int wave) {
  catalogue_detail::StatementUse s(impl_->statement(kFrontier));
  s->bind(1, wave);
  std::vector<Configuration> out;
  while (s->step()) out.push_back(row_to_configuration(*s, impl_->label()));
  return out;
}

std::vector<Configuration> Catalogue::read_all_configurations() {
  catalogue_detail::StatementUse s(impl_->statement(kReadAll));
  std::vector<Configuration> out;
  while (s->step()) out.push_back(row_to_configuration(*s, impl_->label()));
  return out;
}

std::int64_t Catalogue::num_configurations() {
  catalogue_detail::StatementUse s(impl_->statement(kCount));
  s->step();
  return s->column_int(0);
}

bool Catalogue::exists_configuration(ConfigId id) {
  catalogue_detail::StatementUse s(impl_->statement(kExists));
  s->bind(1, id.value());
  return s->step();
}

void Catalogue::update_configuration_status(ConfigId id, ConfigStatus status) {
  catalogue_detail::StatementUse s(impl_->statement(kUpdateStatus));
  s->bind(1, static_cast<int>(status));
  s->bind(2, id.value());
  s->run();
  if (sqlite3_changes(impl_->db->get()) != 1) {
    throw InputError(impl_->label() + ": no configuration with id " + std::to_string(id.value()));
  }
}

void Catalogue::update_configuration_expandable(ConfigId id, bool expandable) {
  catalogue_detail::StatementUse s(impl_->statement(kUpdateExpandable));
  s->bind(1, expandable ? 1 : 0);
  s->bind(2, id.value());
  s->run();
  if (sqlite3_changes(impl_->db->get()) != 1) {
    throw InputError(impl_->label() + ": no configuration with id " + std::to_string(id.value()));
  }
}

std::optional<int> Catalogue::max_wave() {
  catalogue_detail::StatementUse s(impl_->statement(kMaxWave));
  s->step();
  if (s->is_null(0)) return std::nullopt;
  return static_cast<int>(s->column_int(0));
}

Level Catalogue::next_level(CheckpointId checkpoint) {
  catalogue_detail::StatementUse s(impl_->statement(kNextLevel));
  s->bind(1, checkpoint.value());
  s->step();
  return Level(s->column_int(0));
}

ConfigId Catalogue::max_config_id() {
  catalogue_detail::StatementUse s(impl_->statement(kMaxId));
  s->step();
  return s->is_null(0) ? kInvalidConfigId : ConfigId(s->column_int(0));
}

std::set<SegmentId> Catalogue::referenced_segments() {
  catalogue_detail::StatementUse s(impl_->statement(kSegments));
  std::set<SegmentId> segments;
  while (s->step()) segments.insert(SegmentId{s->column_int(0)});
  return segments;
}

}  // namespace hapstate
