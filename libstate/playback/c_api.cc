// The C interface (hapstate/playback_c.h) over the C++ runtime.
#include "hapstate/playback.h"
#include "hapstate/playback_c.h"

#include <cstddef>
#include <cstring>
#include <exception>
#include <new>

struct hs_playback {
  hapstate::PlaybackFile file;
  explicit hs_playback(const char* path) : file(path) {}
};
struct hs_cursor {
  hapstate::HapticCursor cursor;
  hs_cursor(const hapstate::PlaybackFile& f, hapstate::Scheme s) : cursor(f, s) {}
};

static_assert(sizeof(hs_snapshot) == sizeof(hapstate::Snapshot));
static_assert(offsetof(hs_snapshot, weight) == offsetof(hapstate::Snapshot, weight));
static_assert(offsetof(hs_snapshot, corner_configuration) ==
              offsetof(hapstate::Snapshot, corner_configuration));
static_assert(offsetof(hs_snapshot, cell_position) == offsetof(hapstate::Snapshot, cell_position));
static_assert(offsetof(hs_snapshot, corner_shift) == offsetof(hapstate::Snapshot, corner_shift));
static_assert(offsetof(hs_snapshot, scheme) == offsetof(hapstate::Snapshot, scheme));
static_assert(offsetof(hs_snapshot, secant_corners) ==
              offsetof(hapstate::Snapshot, secant_corners));
static_assert(offsetof(hs_snapshot, secant) == offsetof(hapstate::Snapshot, secant));
static_assert(offsetof(hs_snapshot, onset_weight) == offsetof(hapstate::Snapshot, onset_weight));
static_assert(offsetof(hs_snapshot, onset_depth) == offsetof(hapstate::Snapshot, onset_depth));
static_assert(offsetof(hs_snapshot, per_depth) == offsetof(hapstate::Snapshot, per_depth));
static_assert(offsetof(hs_snapshot, depth_source) == offsetof(hapstate::Snapshot, depth_source));
static_assert(offsetof(hs_snapshot, midpoint) == offsetof(hapstate::Snapshot, midpoint));
static_assert(offsetof(hs_snapshot, midpoint_blend) ==
              offsetof(hapstate::Snapshot, midpoint_blend));
static_assert(offsetof(hs_snapshot, sway_position) == offsetof(hapstate::Snapshot, sway_position));

namespace {

void set_error(char* error, std::size_t size, const char* message) {
  if (!error || size == 0) return;
  std::strncpy(error, message, size - 1);
  error[size - 1] = '\0';
}

hapstate::Snapshot to_cpp(const hs_snapshot& s) {
  hapstate::Snapshot out;
  std::memcpy(static_cast<void*>(&out), &s, sizeof(out));
  return out;
}

}  // namespace

extern "C" {

size_t hs_snapshot_size(void) { return sizeof(hapstate::Snapshot); }

int hs_playback_open(const char* path, hs_playback** out, char* error, size_t error_size) {
  *out = nullptr;
  try {
    *out = new hs_playback(path);
    return 0;
  } catch (const std::exception& e) {
    set_error(error, error_size, e.what());
  } catch (...) {
    set_error(error, error_size, "unknown error");
  }
  return -1;
}

int hs_playback_verify(const hs_playback* file, char* error, size_t error_size) {
  try {
    file->file.verify();
    return 0;
  } catch (const std::exception& e) {
    set_error(error, error_size, e.what());
  }
  return -1;
}

void hs_playback_close(hs_playback* file) { delete file; }
int32_t hs_playback_num_view_nodes(const hs_playback* f) { return f->file.num_view_nodes(); }
int32_t hs_playback_num_triangles(const hs_playback* f) {
  return static_cast<int32_t>(f->file.triangles().size() / 3);
}
const float* hs_playback_reference_positions(const hs_playback* f) {
  return f->file.reference_positions().data();
}
const int32_t* hs_playback_triangles(const hs_playback* f) { return f->file.triangles().data(); }
void hs_playback_rest_position(const hs_playback* f, double out[3]) {
  const auto r = f->file.rest_position();
  for (int a = 0; a < 3; ++a) out[a] = r[a];
}

int hs_playback_certificate(const hs_playback* f, hs_certificate* out) {
  const auto c = f->file.certificate();
  if (!c) return 0;
  out->paths = c->paths;
  out->steps_per_path = c->steps_per_path;
  out->steps = c->steps;
  out->failed_steps = c->failed_steps;
  for (int s = 0; s < 2; ++s) {
    out->force_error_worst[s] = c->force_error_worst[s];
    out->force_error_p99[s] = c->force_error_p99[s];
    out->force_error_worst_n[s] = c->force_error_worst_n[s];
    out->deformation_error_worst[s] = c->deformation_error_worst[s];
  }
  out->stiffness_n_per_mm = c->stiffness_n_per_mm;
  out->query_median_ns = c->query_median_ns;
  out->query_p999_ns = c->query_p999_ns;
  return 1;
}

hs_cursor* hs_cursor_create(const hs_playback* file, int scheme) {
  if (scheme != HS_SCHEME_TRILINEAR && scheme != HS_SCHEME_HERMITE) return nullptr;
  return new (std::nothrow) hs_cursor(file->file, static_cast<hapstate::Scheme>(scheme));
}
void hs_cursor_destroy(hs_cursor* cursor) { delete cursor; }
void hs_cursor_reset(hs_cursor* cursor) { cursor->cursor.reset(); }
void hs_cursor_reset_at(hs_cursor* cursor, const double p[3]) {
  cursor->cursor.reset({p[0], p[1], p[2]});
}

int hs_cursor_force(hs_cursor* cursor, const double p[3], double force[3]) {
  const hapstate::Force f = cursor->cursor.force({p[0], p[1], p[2]});
  for (int a = 0; a < 3; ++a) force[a] = f.value[a];
  return f.inside_grid ? 1 : 0;
}

int hs_cursor_force_stiffness(hs_cursor* cursor, const double p[3], double force[3],
                              double stiffness[9]) {
  const hapstate::Force f = cursor->cursor.force({p[0], p[1], p[2]});
  for (int a = 0; a < 3; ++a) force[a] = f.value[a];
  for (int a = 0; a < 9; ++a) stiffness[a] = f.stiffness[a];
  return f.inside_grid ? 1 : 0;
}

void hs_cursor_snapshot(const hs_cursor* cursor, hs_snapshot* out) {
  hapstate::Snapshot s;
  cursor->cursor.snapshot(&s);
  std::memcpy(out, &s, sizeof(s));
}

void hs_deform(const hs_playback* file, const hs_snapshot* snapshot, float* positions) {
  const std::size_t n = 3 * static_cast<std::size_t>(file->file.num_view_nodes());
  hapstate::deform(file->file, to_cpp(*snapshot), std::span<float>(positions, n));
}

}  // extern "C"
