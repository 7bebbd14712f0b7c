// Reading a stored configuration's vectors back from the blobs: the one reader of the touched
// set, for the expansion and the compaction alike.
#pragma once

#include "blobs/blob_store.h"
#include "catalogue/records.h"
#include "statespace/level_match.h"

#include <vector>

namespace hapstate {

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

}  // namespace hapstate
