// Reader for the CalculiX .dat output of a deck written by write_ccx_deck.
#pragma once

#include "problem/problem.h"

#include <Eigen/Core>

#include <filesystem>
#include <string>
#include <vector>

namespace hapstate {

// One printed table of a .dat file, e.g. "displacements (vx,vy,vz) for set NALL and time 2.0".
struct CcxDatBlock {
  std::string quantity;     // first words of the header: "displacements", "forces", "total force"
  std::string set;          // node set name as ccx prints it (upper case)
  double time = 0;          // total time at the print (our decks: step k ends at time k)
  std::vector<int> ids;     // ccx node ids (1-based) per row; empty for "total force"
  Eigen::Matrix3Xd values;  // one column per row, ccx units (m, N)
};

// Parses every 3-component nodal table (U, RF and RF totals) of `dat`, in file order.
// Tables of other kinds are skipped. Throws InputError if the file cannot be read or a table
// row is malformed.
std::vector<CcxDatBlock> read_ccx_dat(const std::filesystem::path& dat);

// The ccx solution at one path point, in hapstate's units and conventions.
struct CcxPathPoint {
  Eigen::Matrix3Xd displacement;  // mesh units, one column per node (0-based ids)
  Eigen::Vector3d force_felt;     // N, force felt by the user = -(sum of ccx RF over probe DOFs)
  Eigen::Vector3d force_on_probe_nodes;  // N, sum of ccx RF over the probe DOFs (support -> body)
};

// The loaded rest state of a deck with gravity (its first step, ending at time 1), mesh units,
// one column per node. Throws InputError if it is missing.
Eigen::Matrix3Xd ccx_rest_displacement(const Problem& problem,
                                       const std::vector<CcxDatBlock>& blocks);

// Results of a deck written by write_ccx_deck(problem, path with `num_points` points): the
// end of path point k's step (time k, or k + 1 after a rest step) gives point k-1. Throws
// InputError if a point is missing (ccx failed before the end) or the tables do not match the
// problem.
std::vector<CcxPathPoint> ccx_path_results(const Problem& problem,
                                           const std::vector<CcxDatBlock>& blocks, int num_points);

}  // namespace hapstate
