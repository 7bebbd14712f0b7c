-- Where the displacements and their slopes d u / d p half-way through a transition's move are
-- stored (with the midpoint force, 0003): blobs/seg-NNNNNN.h5, group midpoint_blob_name
-- ("m<source>_<direction>") holding u (float32, mesh units) and du_dp (float32, 3 columns).
-- With them the playback file interpolates the displacements on the half-spacing cells as it
-- does the force (docs/playback.md). NULL where there is no midpoint force, or where the rows
-- were written before these columns existed.
ALTER TABLE transition ADD COLUMN midpoint_blob_segment INTEGER;
ALTER TABLE transition ADD COLUMN midpoint_blob_name TEXT;
