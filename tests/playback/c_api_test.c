/* The C interface used from C: open (a missing file is an error with a message), verify, a
 * cursor at rest gives zero force, a small move gives a finite force, deform fills every
 * position. Usage: test_playback_c_api PLAYBACK_FILE; exit 0 when every check passes. */
#include "hapstate/playback_c.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int failures = 0;
#define CHECK(cond)                                                      \
  do {                                                                   \
    if (!(cond)) {                                                       \
      fprintf(stderr, "%s:%d: failed: %s\n", __FILE__, __LINE__, #cond); \
      ++failures;                                                        \
    }                                                                    \
  } while (0)

int main(int argc, char** argv) {
  char error[512] = "";
  hs_playback* file = NULL;
  CHECK(hs_snapshot_size() == sizeof(hs_snapshot));
  CHECK(hs_playback_open("/nonexistent/playback.bin", &file, error, sizeof error) == -1);
  CHECK(strstr(error, "/nonexistent/playback.bin") != NULL);
  if (argc < 2) return 2;
  if (hs_playback_open(argv[1], &file, error, sizeof error) != 0) {
    fprintf(stderr, "%s\n", error);
    return 1;
  }
  CHECK(hs_playback_verify(file, error, sizeof error) == 0);
  hs_cursor* cursor = hs_cursor_create(file, HS_SCHEME_HERMITE);
  CHECK(cursor != NULL);
  double rest[3], f[3], p[3];
  hs_playback_rest_position(file, rest);
  CHECK(hs_cursor_force(cursor, rest, f) == 1);
  CHECK(f[0] == 0.0 && f[1] == 0.0 && f[2] == 0.0);
  for (int k = 0; k < 3; ++k) p[k] = rest[k] + 0.01;
  hs_cursor_force(cursor, p, f);
  CHECK(isfinite(f[0]) && isfinite(f[1]) && isfinite(f[2]) && (f[0] != 0.0 || f[1] != 0.0));
  /* The same position with the stiffness: the same force, and the stiffness predicts the
   * force a small step further (first order). */
  double g[3], k[9], q[3], fq[3];
  CHECK(hs_cursor_force_stiffness(cursor, p, g, k) == 1);
  CHECK(g[0] == f[0] && g[1] == f[1] && g[2] == f[2]);
  double knorm = 0.0;
  for (int a = 0; a < 9; ++a) knorm += k[a] * k[a];
  CHECK(knorm > 0.0);
  for (int a = 0; a < 3; ++a) q[a] = p[a] + (a == 2 ? 1e-6 : 0.0);
  hs_cursor_force(cursor, q, fq);
  for (int r = 0; r < 3; ++r)
    CHECK(fabs(fq[r] - f[r] - k[3 * r + 2] * 1e-6) <= 1e-9 * (1.0 + sqrt(knorm)));
  hs_snapshot snapshot;
  hs_cursor_snapshot(cursor, &snapshot);
  CHECK(snapshot.sequence == 4);
  const int n = hs_playback_num_view_nodes(file);
  float* positions = malloc(sizeof(float) * 3 * (size_t)(n > 0 ? n : 1));
  for (int k = 0; k < 3 * n; ++k) positions[k] = NAN;
  hs_deform(file, &snapshot, positions);
  for (int k = 0; k < 3 * n; ++k) CHECK(isfinite(positions[k]));
  free(positions);
  /* Placed back at rest from afar (the grab probe's only zero configuration): zero force. */
  hs_cursor_reset_at(cursor, p);
  CHECK(hs_cursor_force(cursor, rest, f) == 1);
  CHECK(f[0] == 0.0 && f[1] == 0.0 && f[2] == 0.0);
  hs_cursor_destroy(cursor);
  hs_playback_close(file);
  return failures == 0 ? 0 : 1;
}
