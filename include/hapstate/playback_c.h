/* hapstate playback runtime: C interface for haptic frameworks in C or other languages
 * (docs/playback.md). Link hapstate::playback. Functions that can fail return 0 on success
 * and -1 on failure, with the reason in the caller's buffer `error` (may be NULL).
 *
 *   hs_playback* file; char err[512];
 *   if (hs_playback_open("state/playback.bin", &file, err, sizeof err) != 0) { puts(err); ... }
 *   hs_cursor* cursor = hs_cursor_create(file, HS_SCHEME_HERMITE);
 *   haptic thread:  hs_cursor_force(cursor, p, f);          no allocation, lock or syscall
 *                   (hs_cursor_force_stiffness(cursor, p, f, k) with the 3 x 3 stiffness)
 *   visual thread:  hs_cursor_snapshot(cursor, &s); hs_deform(file, &s, positions);
 */
#ifndef HAPSTATE_PLAYBACK_C_H
#define HAPSTATE_PLAYBACK_C_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct hs_playback hs_playback;
typedef struct hs_cursor hs_cursor;

enum { HS_SCHEME_TRILINEAR = 0, HS_SCHEME_HERMITE = 1 };

/* What the visual thread needs of a cursor (same layout as hapstate::Snapshot). */
typedef struct hs_snapshot {
  uint64_t sequence;
  double probe[3];
  double force[3];
  int32_t corner_configuration[8];
  double weight[8];
  double cell_position[3];
  int32_t corner_shift[8][3];
  int32_t scheme;         /* HS_SCHEME_*: how hs_deform interpolates the displacements */
  int32_t secant_corners; /* bit c: corner c takes its source's displacements scaled by secant[c] */
  double secant[8][4];
  double onset_weight;
  double onset_depth;
  double per_depth[8];
  int32_t depth_source[8];
  int32_t midpoint[27]; /* 0, or 1 + the stored midpoint whose displacements hold at that point */
  double midpoint_blend[27][6]; /* near the contact onset: the blend at those points */
  /* refined contact cell: where the far nodes are interpolated (a hand-built snapshot sets it
   * equal to cell_position) */
  double sway_position[3];
} hs_snapshot;

/* sizeof(hs_snapshot) in the library as built. hs_snapshot grows when the playback format does
 * (it gained `midpoint` with format 7, `midpoint_blend` within format 8 on 2026-11-26,
 * `sway_position` on 2026-11-28): a program
 * that loads the library at run time should check hs_snapshot_size() == sizeof(hs_snapshot) before
 * its first snapshot. */
size_t hs_snapshot_size(void);

int hs_playback_open(const char* path, hs_playback** out, char* error, size_t error_size);
int hs_playback_verify(const hs_playback* file, char* error, size_t error_size);
void hs_playback_close(hs_playback* file);
int32_t hs_playback_num_view_nodes(const hs_playback* file);
int32_t hs_playback_num_triangles(const hs_playback* file);
const float* hs_playback_reference_positions(const hs_playback* file); /* 3 per view node */
const int32_t* hs_playback_triangles(const hs_playback* file);         /* 3 per triangle */
void hs_playback_rest_position(const hs_playback* file, double out[3]);

/* What hapstate-certify measured on the file (PlaybackFile::certificate, docs/certificate.md);
 * arrays indexed by scheme (HS_SCHEME_TRILINEAR, HS_SCHEME_HERMITE). */
typedef struct hs_certificate {
  int32_t paths, steps_per_path, steps, failed_steps;
  double force_error_worst[2], force_error_p99[2]; /* of the path's largest force */
  double force_error_worst_n[2];                   /* N */
  double deformation_error_worst[2];
  double stiffness_n_per_mm;
  double query_median_ns, query_p999_ns;
} hs_certificate;
/* 1 and *out filled when the file holds a certificate measured by this library's playback code, 0
 * when hapstate-certify has not run (or was run by another version: PlaybackFile::certificate). */
int hs_playback_certificate(const hs_playback* file, hs_certificate* out);

hs_cursor* hs_cursor_create(const hs_playback* file, int scheme); /* NULL on a bad scheme */
void hs_cursor_destroy(hs_cursor* cursor);
void hs_cursor_reset(hs_cursor* cursor);
/* The probe placed at p with the body at rest (HapticCursor::reset(p)); not in the haptic loop. */
void hs_cursor_reset_at(hs_cursor* cursor, const double p[3]);
/* Force (N) at probe position p (mesh units); returns 1 inside the grid, 0 outside. */
int hs_cursor_force(hs_cursor* cursor, const double p[3], double force[3]);
/* The same, with the stiffness d(force)/d(p) (N per mesh unit, row-major 3 x 3) for stable
 * rendering and the device's stiffness limit (Force::stiffness, docs/playback.md). */
int hs_cursor_force_stiffness(hs_cursor* cursor, const double p[3], double force[3],
                              double stiffness[9]);
void hs_cursor_snapshot(const hs_cursor* cursor, hs_snapshot* out);
/* positions: 3 * num_view_nodes floats. */
void hs_deform(const hs_playback* file, const hs_snapshot* snapshot, float* positions);

#ifdef __cplusplus
}
#endif

#endif
