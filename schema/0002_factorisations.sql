-- Numeric factorisations a transition's solve spent (fallbacks and, for a transition that made a
-- new configuration, its haptic stiffness included): the cost measure of the expansion.
-- Rows written before this column existed count 0.
ALTER TABLE transition ADD COLUMN factorisations INTEGER NOT NULL DEFAULT 0 CHECK (factorisations >= 0);
