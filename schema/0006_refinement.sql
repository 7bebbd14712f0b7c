-- Local refinement (docs/state-space.md, "Refined cells"): the force and the haptic stiffness at
-- the quarter-spacing lattice points of a cell whose force the half-spacing data do not resolve.
-- A cell is named by the configuration at its lowest corner; its other corners are the targets
-- of that configuration's moves in the 7 directions with offsets >= 0. `point` numbers the
-- 5 x 5 x 5 lattice of the cell (25 i + 5 j + k, i, j, k quarter steps along x, y, z); only the
-- points that are not corners, edge midpoints, face or cell centres (those the moves recorded)
-- are stored, all of a cell in one transaction. outcome 0: solved (force and stiffness set),
-- 2: the solve failed (failure_reason says why; the cursor interpolates there).
CREATE TABLE refinement (
  cell              INTEGER NOT NULL REFERENCES configuration (id),
  point             INTEGER NOT NULL CHECK (point BETWEEN 0 AND 124),
  outcome           INTEGER NOT NULL CHECK (outcome IN (0, 2)),
  fx REAL, fy REAL, fz REAL,                            -- felt by the user, N
  k0 REAL, k1 REAL, k2 REAL, k3 REAL, k4 REAL, k5 REAL, k6 REAL, k7 REAL, k8 REAL,  -- N per mesh unit
  newton_iterations INTEGER NOT NULL CHECK (newton_iterations >= 0),
  wall_ms           REAL NOT NULL CHECK (wall_ms >= 0),
  failure_reason    TEXT NOT NULL DEFAULT '',
  PRIMARY KEY (cell, point),
  CHECK ((outcome = 0) = (fx IS NOT NULL))
) WITHOUT ROWID;
