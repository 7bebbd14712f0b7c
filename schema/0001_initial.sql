-- hapstate catalogue, schema version 1 (docs/storage.md describes every column).
-- Applied by the library in one transaction, followed by PRAGMA user_version = 1.
-- Units: lengths in mesh units, forces in N, stiffness in N per mesh unit, times in ms.

-- The scene this state directory was built from (exactly one row once imported).
CREATE TABLE scene (
  id                     INTEGER PRIMARY KEY CHECK (id = 1),
  text                   TEXT NOT NULL,                 -- scene.toml as read
  hash                   TEXT NOT NULL,                 -- content hash of text (16 hex digits)
  mesh_file              TEXT NOT NULL,                 -- as named in the scene
  mesh_hash              TEXT NOT NULL,                 -- content hash of the mesh file
  mesh_nodes             INTEGER NOT NULL CHECK (mesh_nodes >= 0),
  mesh_elements          INTEGER NOT NULL CHECK (mesh_elements >= 0),
  mesh_surface_triangles INTEGER NOT NULL CHECK (mesh_surface_triangles >= 0),
  bbox_min_x REAL NOT NULL, bbox_min_y REAL NOT NULL, bbox_min_z REAL NOT NULL,
  bbox_max_x REAL NOT NULL, bbox_max_y REAL NOT NULL, bbox_max_z REAL NOT NULL,
  volume                 REAL NOT NULL                  -- mesh units^3
);

-- One row per execution of a stage; inputs in stage_run_input.
CREATE TABLE stage_run (
  id               INTEGER PRIMARY KEY,
  stage            TEXT NOT NULL,                       -- "import", "grid", "expand", ...
  parameters       TEXT NOT NULL,                       -- resolved options (free text)
  hapstate_version TEXT NOT NULL,
  started_ms       INTEGER NOT NULL,                    -- Unix time, ms, UTC
  ended_ms         INTEGER,                             -- NULL while running (or crashed)
  outcome          TEXT NOT NULL CHECK (outcome IN
                     ('running', 'ok', 'unchanged', 'partial', 'failed')),
  message          TEXT NOT NULL DEFAULT ''
);
CREATE INDEX stage_run_by_stage ON stage_run (stage, id);

CREATE TABLE stage_run_input (
  run  INTEGER NOT NULL REFERENCES stage_run (id) ON DELETE CASCADE,
  name TEXT NOT NULL,                                   -- "scene", "mesh", "material", ...
  hash TEXT NOT NULL,                                   -- content hash (16 hex digits)
  PRIMARY KEY (run, name)
) WITHOUT ROWID;

-- Grid check-points P_ijk = origin + (i, j, k) * spacing.
CREATE TABLE checkpoint (
  id             INTEGER PRIMARY KEY,
  i              INTEGER NOT NULL,
  j              INTEGER NOT NULL,
  k              INTEGER NOT NULL,
  x REAL NOT NULL, y REAL NOT NULL, z REAL NOT NULL,    -- position, mesh units
  classification INTEGER NOT NULL CHECK (classification BETWEEN 0 AND 4),
  UNIQUE (i, j, k)
);

-- Equilibrium configurations: levels of a check-point.
CREATE TABLE configuration (
  id           INTEGER PRIMARY KEY,
  checkpoint   INTEGER NOT NULL REFERENCES checkpoint (id),
  level        INTEGER NOT NULL CHECK (level >= 0),
  wave         INTEGER NOT NULL CHECK (wave >= 0),      -- BFS distance from a zero configuration
  force_x REAL NOT NULL, force_y REAL NOT NULL, force_z REAL NOT NULL,  -- felt by the user, N
  -- haptic stiffness d(force)/d(probe position), row-major, N per mesh unit
  k_xx REAL NOT NULL, k_xy REAL NOT NULL, k_xz REAL NOT NULL,
  k_yx REAL NOT NULL, k_yy REAL NOT NULL, k_yz REAL NOT NULL,
  k_zx REAL NOT NULL, k_zy REAL NOT NULL, k_zz REAL NOT NULL,
  expandable   INTEGER NOT NULL CHECK (expandable IN (0, 1)),
  status       INTEGER NOT NULL CHECK (status BETWEEN 0 AND 2),  -- 0 open, 1 expanded, 2 merged
  blob_segment INTEGER CHECK (blob_segment >= 1),       -- blobs/seg-NNNNNN.h5
  blob_name    TEXT,                                    -- group in it: vectors <name>/u, /t, /h
  summary      BLOB NOT NULL,                           -- float64 little-endian sketch
  UNIQUE (checkpoint, level),
  CHECK ((blob_segment IS NULL) = (blob_name IS NULL))
);
CREATE INDEX configuration_frontier ON configuration (wave, status) WHERE expandable = 1;
CREATE INDEX configuration_by_segment ON configuration (blob_segment);

-- Moves of the probe from a configuration to a neighbouring check-point.
CREATE TABLE transition (
  source            INTEGER NOT NULL REFERENCES configuration (id),
  direction         INTEGER NOT NULL CHECK (direction BETWEEN 0 AND 25),
  outcome           INTEGER NOT NULL CHECK (outcome BETWEEN 0 AND 2),  -- 0 reached, 1 outside, 2 failed
  target            INTEGER REFERENCES configuration (id),
  substeps          INTEGER NOT NULL CHECK (substeps >= 0),
  newton_iterations INTEGER NOT NULL CHECK (newton_iterations >= 0),
  final_residual    REAL NOT NULL,                      -- N
  wall_ms           REAL NOT NULL CHECK (wall_ms >= 0),
  failure_reason    TEXT NOT NULL DEFAULT '',
  PRIMARY KEY (source, direction),
  CHECK ((outcome = 0) = (target IS NOT NULL))
) WITHOUT ROWID;
CREATE INDEX transition_by_target ON transition (target);
