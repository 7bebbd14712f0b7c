-- The force the user feels half-way through a transition's move (N), solved on the way to the
-- target for the directions whose offsets are all >= 0: the value of the force at an edge
-- midpoint, a face centre or a cell centre of the grid, along the move's own history. The
-- playback file interpolates with it between check-points (docs/playback.md). NULL: not solved
-- (other directions, failed or outside moves, rows written before this column existed).
ALTER TABLE transition ADD COLUMN midpoint_fx REAL;
ALTER TABLE transition ADD COLUMN midpoint_fy REAL;
ALTER TABLE transition ADD COLUMN midpoint_fz REAL;
