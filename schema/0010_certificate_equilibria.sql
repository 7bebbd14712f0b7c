-- The certificate's two-sided solves (docs/certificate.md, "When it is not good enough"): at a
-- worst step of the certificate, the precise solver reaches the probe position from rest by way
-- of the position - along and of the position + along (along: half the grid spacing on one
-- axis). Two different forces are two equilibria: a jump no spacing or refinement removes. One
-- row per step and axis, measured on the playback file of playback_hash (as certificate_path);
-- rows of another file, or of a step whose path is gone, are stale and deleted with it.
CREATE TABLE certificate_equilibria (
  seed          INTEGER NOT NULL CHECK (seed >= 1),
  step          INTEGER NOT NULL CHECK (step >= 1),
  axis          INTEGER NOT NULL CHECK (axis BETWEEN 0 AND 2),
  playback_hash TEXT NOT NULL,
  along         REAL NOT NULL CHECK (along > 0),   -- mesh units, on that axis
  verdict       TEXT NOT NULL CHECK (verdict IN ('one', 'two', 'ends', 'undecided')),
  minus_fx REAL, minus_fy REAL, minus_fz REAL,     -- N, by way of - along; NULL: Newton failed
  plus_fx REAL, plus_fy REAL, plus_fz REAL,        -- N, by way of + along; NULL: Newton failed
  wall_ms       REAL NOT NULL CHECK (wall_ms >= 0),
  PRIMARY KEY (seed, step, axis)
) WITHOUT ROWID;
