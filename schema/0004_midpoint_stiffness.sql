-- The haptic stiffness d(force)/d(probe) half-way through a transition's move (N per mesh unit,
-- row-major), solved with the midpoint force (0003): with it the playback file interpolates each
-- cell as eight half-spacing cells of cubic Hermite (docs/playback.md). NULL where the midpoint
-- force is NULL, or where the rows were written before this column existed.
ALTER TABLE transition ADD COLUMN midpoint_k0 REAL;
ALTER TABLE transition ADD COLUMN midpoint_k1 REAL;
ALTER TABLE transition ADD COLUMN midpoint_k2 REAL;
ALTER TABLE transition ADD COLUMN midpoint_k3 REAL;
ALTER TABLE transition ADD COLUMN midpoint_k4 REAL;
ALTER TABLE transition ADD COLUMN midpoint_k5 REAL;
ALTER TABLE transition ADD COLUMN midpoint_k6 REAL;
ALTER TABLE transition ADD COLUMN midpoint_k7 REAL;
ALTER TABLE transition ADD COLUMN midpoint_k8 REAL;
