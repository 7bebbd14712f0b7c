// Tables certificate_path, certificate_step, certificate (schema 7) and certificate_equilibria
// (schema 10): what hapstate-certify measured.
#include "catalogue/catalogue_impl.hpp"
#include "util/error.h"

#include <map>

namespace hapstate {
namespace {

// The verdicts' names, in the enum's order.
constexpr const char* kEquilibriaNames[] = {"one", "two", "ends", "undecided"};

Equilibria parse_equilibria(const std::string& text, const std::string& label) {
  for (int e = 0; e < 4; ++e)
    if (text == kEquilibriaNames[e]) return static_cast<Equilibria>(e);
  throw InputError(label + ": damaged catalogue: certificate_equilibria.verdict = '" + text +
                   "', not one of one, two, ends, undecided");
}

constexpr const char* kInsertPath =
    "INSERT INTO certificate_path (seed, playback_hash, steps, max_force, failures, wall_ms) "
    "VALUES (?, ?, ?, ?, ?, ?)";
#define HAPSTATE_CERTIFICATE_STEP_COLUMNS                                             \
  "seed, step, x, y, z, i, j, k, ni, nj, nk, force, solved, onset, trilinear_error, " \
  "hermite_error, trilinear_deformation, hermite_deformation"
constexpr const char* kInsertStep =
    "INSERT INTO certificate_step (" HAPSTATE_CERTIFICATE_STEP_COLUMNS
    ") VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)";
constexpr const char* kReadSteps =
    "SELECT " HAPSTATE_CERTIFICATE_STEP_COLUMNS " FROM certificate_step ORDER BY seed, step";
#undef HAPSTATE_CERTIFICATE_STEP_COLUMNS
constexpr const char* kReadPaths =
    "SELECT seed, playback_hash, steps, max_force, failures, wall_ms FROM certificate_path "
    "ORDER BY seed";
#define HAPSTATE_STALE "WHERE playback_hash <> ?1 OR steps <> ?2 OR seed > ?3"
constexpr const char* kCountStale = "SELECT count(*) FROM certificate_path " HAPSTATE_STALE;
constexpr const char* kDeleteStaleSteps =
    "DELETE FROM certificate_step WHERE seed IN (SELECT seed FROM certificate_path " HAPSTATE_STALE
    ")";
constexpr const char* kDeleteStalePaths = "DELETE FROM certificate_path " HAPSTATE_STALE;
#undef HAPSTATE_STALE
constexpr const char* kDeleteStaleEquilibria =
    "DELETE FROM certificate_equilibria WHERE playback_hash <> ?1 OR seed NOT IN (SELECT seed "
    "FROM certificate_path WHERE steps = ?2 AND seed <= ?3)";
#define HAPSTATE_EQUILIBRIA_COLUMNS                                                          \
  "seed, step, axis, playback_hash, along, verdict, minus_fx, minus_fy, minus_fz, plus_fx, " \
  "plus_fy, plus_fz, wall_ms"
constexpr const char* kInsertEquilibria =
    "INSERT INTO certificate_equilibria (" HAPSTATE_EQUILIBRIA_COLUMNS
    ") VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)";
constexpr const char* kReadEquilibria =
    "SELECT " HAPSTATE_EQUILIBRIA_COLUMNS " FROM certificate_equilibria ORDER BY seed, step, axis";
#undef HAPSTATE_EQUILIBRIA_COLUMNS
constexpr const char* kDeleteStaleRun =
    "DELETE FROM certificate WHERE playback_hash <> ?1 OR steps <> ?2 OR paths <> ?3";
constexpr const char* kWriteRun =
    "INSERT OR REPLACE INTO certificate (id, playback_hash, paths, steps, queries, "
    "query_median_ns, query_p999_ns, stiffness, ended_ms) VALUES (1, ?, ?, ?, ?, ?, ?, ?, ?)";
constexpr const char* kDeleteRun = "DELETE FROM certificate";
constexpr const char* kReadRun =
    "SELECT playback_hash, paths, steps, queries, query_median_ns, query_p999_ns, stiffness, "
    "ended_ms FROM certificate WHERE id = 1";

}  // namespace

void Catalogue::insert_certificate_path(const CertificatePath& path) {
  catalogue_detail::Savepoint savepoint(*impl_->db);
  {
    catalogue_detail::StatementUse s(impl_->statement(kInsertPath));
    s->bind(1, path.seed);
    s->bind(2, path.playback_hash.hex());
    s->bind(3, path.steps);
    s->bind(4, path.max_force);
    s->bind(5, path.failures);
    s->bind(6, path.wall_ms);
    s->run();
  }
  for (const CertificateStep& r : path.rows) {
    catalogue_detail::StatementUse s(impl_->statement(kInsertStep));
    s->bind(1, path.seed);
    s->bind(2, r.step);
    for (int a = 0; a < 3; ++a) s->bind(3 + a, r.probe[a]);
    for (int a = 0; a < 3; ++a) s->bind(6 + a, r.cell[a]);
    for (int a = 0; a < 3; ++a) s->bind(9 + a, r.checkpoint[a]);
    s->bind(12, r.force);
    s->bind(13, r.solved ? 1 : 0);
    s->bind(14, r.onset ? 1 : 0);
    s->bind(15, r.error[0]);
    s->bind(16, r.error[1]);
    s->bind(17, r.deformation[0]);
    s->bind(18, r.deformation[1]);
    s->run();
  }
  savepoint.release();
}

std::vector<CertificatePath> Catalogue::read_all_certificate_paths() {
  std::vector<CertificatePath> out;
  std::map<int, std::size_t> index;
  {
    catalogue_detail::StatementUse s(impl_->statement(kReadPaths));
    while (s->step()) {
      CertificatePath p;
      p.seed = static_cast<int>(s->column_int(0));
      p.playback_hash = ContentHash::from_hex(s->column_text(1));
      p.steps = static_cast<int>(s->column_int(2));
      p.max_force = s->column_double(3);
      p.failures = static_cast<int>(s->column_int(4));
      p.wall_ms = s->column_double(5);
      index[p.seed] = out.size();
      out.push_back(std::move(p));
    }
  }
  catalogue_detail::StatementUse s(impl_->statement(kReadSteps));
  while (s->step()) {
    const auto it = index.find(static_cast<int>(s->column_int(0)));
    if (it == index.end()) continue;  // the foreign key makes this impossible
    CertificateStep r;
    r.step = static_cast<int>(s->column_int(1));
    for (int a = 0; a < 3; ++a) r.probe[a] = s->column_double(2 + a);
    for (int a = 0; a < 3; ++a) r.cell[a] = static_cast<int>(s->column_int(5 + a));
    for (int a = 0; a < 3; ++a) r.checkpoint[a] = static_cast<int>(s->column_int(8 + a));
    r.force = s->column_double(11);
    r.solved = s->column_int(12) != 0;
    r.onset = s->column_int(13) != 0;
    r.error = {s->column_double(14), s->column_double(15)};
    r.deformation = {s->column_double(16), s->column_double(17)};
    out[it->second].rows.push_back(r);
  }
  return out;
}

std::int64_t Catalogue::delete_stale_certificate(const ContentHash& playback_hash, int steps,
                                                 int paths) {
  catalogue_detail::Savepoint savepoint(*impl_->db);
  std::int64_t stale = 0;
  {
    catalogue_detail::StatementUse s(impl_->statement(kCountStale));
    s->bind(1, playback_hash.hex());
    s->bind(2, steps);
    s->bind(3, paths);
    s->step();
    stale = s->column_int(0);
  }
  for (const char* sql :
       {kDeleteStaleSteps, kDeleteStalePaths, kDeleteStaleEquilibria, kDeleteStaleRun}) {
    catalogue_detail::StatementUse s(impl_->statement(sql));
    s->bind(1, playback_hash.hex());
    s->bind(2, steps);
    s->bind(3, paths);
    s->run();
  }
  savepoint.release();
  return stale;
}

const char* equilibria_name(Equilibria e) { return kEquilibriaNames[static_cast<int>(e)]; }

void Catalogue::insert_certificate_equilibria(const std::vector<CertificateEquilibria>& rows) {
  catalogue_detail::Savepoint savepoint(*impl_->db);
  for (const CertificateEquilibria& r : rows) {
    catalogue_detail::StatementUse s(impl_->statement(kInsertEquilibria));
    s->bind(1, r.seed);
    s->bind(2, r.step);
    s->bind(3, r.axis);
    s->bind(4, r.playback_hash.hex());
    s->bind(5, r.along);
    s->bind(6, std::string_view(equilibria_name(r.verdict)));
    for (int side = 0; side < 2; ++side) {
      const auto& f = side == 0 ? r.force_minus : r.force_plus;
      for (int a = 0; a < 3; ++a)
        if (f)
          s->bind(7 + 3 * side + a, (*f)[a]);
        else
          s->bind_null(7 + 3 * side + a);
    }
    s->bind(13, r.wall_ms);
    s->run();
  }
  savepoint.release();
}

std::vector<CertificateEquilibria> Catalogue::read_all_certificate_equilibria() {
  std::vector<CertificateEquilibria> out;
  catalogue_detail::StatementUse s(impl_->statement(kReadEquilibria));
  while (s->step()) {
    CertificateEquilibria r;
    r.seed = static_cast<int>(s->column_int(0));
    r.step = static_cast<int>(s->column_int(1));
    r.axis = static_cast<int>(s->column_int(2));
    r.playback_hash = ContentHash::from_hex(s->column_text(3));
    r.along = s->column_double(4);
    r.verdict = parse_equilibria(s->column_text(5), impl_->label());
    for (int side = 0; side < 2; ++side) {
      if (s->is_null(6 + 3 * side)) continue;
      std::array<double, 3> f{};
      for (int a = 0; a < 3; ++a) f[a] = s->column_double(6 + 3 * side + a);
      (side == 0 ? r.force_minus : r.force_plus) = f;
    }
    r.wall_ms = s->column_double(12);
    out.push_back(std::move(r));
  }
  return out;
}

void Catalogue::write_certificate(const CertificateRun& run) {
  catalogue_detail::StatementUse s(impl_->statement(kWriteRun));
  s->bind(1, run.playback_hash.hex());
  s->bind(2, run.paths);
  s->bind(3, run.steps);
  s->bind(4, run.queries);
  s->bind(5, run.query_median_ns);
  s->bind(6, run.query_p999_ns);
  s->bind(7, run.stiffness);
  s->bind(8, static_cast<std::int64_t>(run.ended.time_since_epoch().count()));
  s->run();
}

void Catalogue::delete_certificate() {
  catalogue_detail::StatementUse s(impl_->statement(kDeleteRun));
  s->run();
}

std::optional<CertificateRun> Catalogue::read_certificate() {
  catalogue_detail::StatementUse s(impl_->statement(kReadRun));
  if (!s->step()) return std::nullopt;
  CertificateRun r;
  r.playback_hash = ContentHash::from_hex(s->column_text(0));
  r.paths = static_cast<int>(s->column_int(1));
  r.steps = static_cast<int>(s->column_int(2));
  r.queries = s->column_int(3);
  r.query_median_ns = s->column_double(4);
  r.query_p999_ns = s->column_double(5);
  r.stiffness = s->column_double(6);
  r.ended = TimeMs(std::chrono::milliseconds(s->column_int(7)));
  return r;
}

}  // namespace hapstate
