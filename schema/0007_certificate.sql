-- The certificate (hapstate-certify, docs/certificate.md): the paper's experiment, the precise
-- solver against the haptic cursors, on seeded random paths over the workspace, measured on one
-- playback file (playback_hash, 16 hex digits: the file's source hash as hapstate-index wrote it;
-- since 2026-11-28 that hash and the playback code's id hashed together, docs/certificate.md). A
-- path's row and its steps are written in one transaction, so an interrupted run resumes at the
-- paths not stored yet. Rows measured on another playback file (or by other code) are stale: the
-- next run deletes them first.
CREATE TABLE certificate_path (
  seed          INTEGER PRIMARY KEY CHECK (seed >= 1),
  playback_hash TEXT NOT NULL,
  steps         INTEGER NOT NULL CHECK (steps >= 1),
  max_force     REAL NOT NULL CHECK (max_force >= 0),     -- N: the largest precise |f*| of the path
  failures      INTEGER NOT NULL CHECK (failures >= 0),   -- steps whose precise solve failed
  wall_ms       REAL NOT NULL CHECK (wall_ms >= 0)
);

-- One step of a path: where the probe was, the precise force, each scheme's force error in N
-- (relative errors divide by the path's max_force, as hapstate-eval) and deformation error
-- ||u - u*|| / ||u*|| over the surface nodes (eval's rule for a body near rest).
CREATE TABLE certificate_step (
  seed    INTEGER NOT NULL REFERENCES certificate_path (seed) ON DELETE CASCADE,
  step    INTEGER NOT NULL CHECK (step >= 1),
  x REAL NOT NULL, y REAL NOT NULL, z REAL NOT NULL,      -- probe, mesh units
  i INTEGER NOT NULL, j INTEGER NOT NULL, k INTEGER NOT NULL,  -- grid index of the cell's lowest corner
  ni INTEGER NOT NULL, nj INTEGER NOT NULL, nk INTEGER NOT NULL,  -- grid index of the nearest check-point
  force   REAL NOT NULL,                                  -- |f*|, N (0 if not solved)
  solved  INTEGER NOT NULL CHECK (solved IN (0, 1)),      -- 0: left out of every statistic
  onset   INTEGER NOT NULL CHECK (onset IN (0, 1)),       -- contact onset: out of the deformation's
  trilinear_error       REAL NOT NULL,                    -- |f - f*|, N
  hermite_error         REAL NOT NULL,
  trilinear_deformation REAL NOT NULL,
  hermite_deformation   REAL NOT NULL,
  PRIMARY KEY (seed, step)
) WITHOUT ROWID;

-- What the run measured once all its paths were stored: the haptic query's time along them and
-- the largest stored stiffness (one row, replaced by each complete run).
CREATE TABLE certificate (
  id             INTEGER PRIMARY KEY CHECK (id = 1),
  playback_hash  TEXT NOT NULL,
  paths          INTEGER NOT NULL CHECK (paths >= 1),
  steps          INTEGER NOT NULL CHECK (steps >= 1),
  queries        INTEGER NOT NULL CHECK (queries >= 0),  -- Hermite force() calls timed
  query_median_ns REAL NOT NULL,
  query_p999_ns  REAL NOT NULL,
  stiffness      REAL NOT NULL,                          -- N/m: the largest |eigenvalue| stored
  ended_ms       INTEGER NOT NULL
);
