-- Refinement depth 3 (docs/state-space.md, "hapstate-refine"): a refined cell may also have
-- points of its sixteenth-spacing lattice, numbered 854 + 289 i + 17 j + k (i, j, k sixteenth
-- steps along x, y, z; only those with an odd step, and only in the eighth cells the stage
-- flagged). SQLite cannot change a CHECK constraint, so the table is made anew with the wider
-- range and its rows copied.
CREATE TABLE refinement_new (
  cell              INTEGER NOT NULL REFERENCES configuration (id),
  point             INTEGER NOT NULL CHECK (point BETWEEN 0 AND 5766),
  outcome           INTEGER NOT NULL CHECK (outcome IN (0, 2)),
  fx REAL, fy REAL, fz REAL,                            -- felt by the user, N
  k0 REAL, k1 REAL, k2 REAL, k3 REAL, k4 REAL, k5 REAL, k6 REAL, k7 REAL, k8 REAL,  -- N per mesh unit
  newton_iterations INTEGER NOT NULL CHECK (newton_iterations >= 0),
  wall_ms           REAL NOT NULL CHECK (wall_ms >= 0),
  failure_reason    TEXT NOT NULL DEFAULT '',
  PRIMARY KEY (cell, point),
  CHECK ((outcome = 0) = (fx IS NOT NULL))
) WITHOUT ROWID;
INSERT INTO refinement_new SELECT * FROM refinement;
DROP TABLE refinement;
ALTER TABLE refinement_new RENAME TO refinement;
