// A stored configuration's vectors (ConfigVectors, laid out as VectorLayout says) and reading
// them back from the blobs: the one reader of the touched set, for the expansion and the
// compaction alike.
#pragma once

#include "blobs/blob_store.h"
#include "blobs/segment_writer.h"
#include "catalogue/records.h"

#include <span>
#include <vector>

namespace hapstate {

// The vectors of a configuration: u (3 per node, mesh units), t (probe DOFs, mesh units),
// h (reactions at the probe DOFs, N); sticking contact: touched (the nodes the sphere holds,
// ascending; their 3 DOFs each are the probe DOFs of t and h, in that order); frictionless
// contact: h is the sphere's resultant force on the body (VectorLayout below).
struct ConfigVectors {
  std::vector<double> u, t, h;
  std::vector<int> touched;
  std::vector<double> multipliers;  // frictionless contact: (triangle, N) pairs; not compared
};

// What a configuration stores besides u (ProbeModel::layout(): one definition for the loader,
// the writer and the level comparison). Grab: t and h have a value per grabbed DOF; sticking
// contact: the touched set is stored ("<blob>/touched") and t and h have 3 values per touched
// node; frictionless contact: t is empty, h the 3 components of the sphere's force on the
// body, and the contact multipliers are stored ("<blob>/multipliers") to warm-start the moves
// from the configuration (they do not define it: level comparison ignores them).
struct VectorLayout {
  bool touched = false;      // "<blob>/touched" is stored; t and h: 3 values per touched node
  int load_size = 0;         // otherwise: the values of t
  int reaction_size = 0;     // otherwise: the values of h
  bool multipliers = false;  // "<blob>/multipliers" is stored
  int t_size(std::size_t touched_nodes) const {
    return touched ? 3 * static_cast<int>(touched_nodes) : load_size;
  }
  int h_size(std::size_t touched_nodes) const {
    return touched ? 3 * static_cast<int>(touched_nodes) : reaction_size;
  }
};

// The touched set of a sticking-contact configuration, '<name>/touched' of its blob: node ids
// in [0, num_nodes), strictly ascending (empty for a configuration without a blob). Throws
// InputError naming the segment and configuration otherwise.
std::vector<int> read_touched_set(const BlobStore& blobs, const Configuration& c, int num_nodes);

// The vectors of a stored configuration: from its blob, or for one without a blob (the zero
// configuration: nothing touched, no force) u = `rest_u` (rest_displacements(problem): the
// loaded rest state, zeros without loads; its size is the problem's DOFs) and zeros, laid out
// as `layout` says (the touched set read from <name>/touched where it is stored). Throws
// InputError naming the segment and vector if they cannot be read or have the wrong sizes.
ConfigVectors load_config_vectors(const BlobStore& blobs, const Configuration& c,
                                  const std::vector<double>& rest_u, const VectorLayout& layout);

// What level comparison (compaction) reads: the vectors u and h of `c` ("<blob>/u", "/h"; t is not
// compared) and, for a sticking contact probe, its touched set ("/touched", read_touched_set:
// configurations with different sets are never merged); empty when `c` has no blob (a zero state).
// Throws InputError naming the segment and vector if one is missing, unreadable or (the touched
// set) not ascending node ids.
ConfigVectors load_level_vectors(const BlobStore& blobs, const Configuration& c,
                                 const std::vector<double>& rest_u);

// Writes a new configuration's vectors under its blob's name (`blob`): u, t, h, the displacement
// slopes du_dp when given (float32, for the Hermite deformation), and what `layout` says is
// stored besides (the touched set, the contact multipliers). The inverse of load_config_vectors.
void write_config_vectors(SegmentWriter& writer, const BlobRef& blob, const ConfigVectors& v,
                          std::span<const float> du_dp, const VectorLayout& layout);

// Writes a transition's midpoint state (u and du_dp, float32) under its midpoint blob's name.
void write_midpoint_vectors(SegmentWriter& writer, const BlobRef& blob, std::span<const float> u,
                            std::span<const float> du_dp);

}  // namespace hapstate
