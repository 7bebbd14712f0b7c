#include "statedir/config_vectors.h"

#include "util/error.h"

#include <string>

namespace hapstate {

std::vector<int> read_touched_set(const BlobStore& blobs, const Configuration& c, int num_nodes) {
  std::vector<int> touched;
  if (!c.blob) return touched;
  for (double n : blobs.read(c.blob->segment, c.blob->dataset(BlobVector::kTouched))) {
    if (n < 0 || n >= num_nodes || n != static_cast<int>(n) ||
        (!touched.empty() && n <= touched.back())) {
      throw InputError((blobs.directory() / segment_file_name(c.blob->segment)).string() + ": '" +
                       c.blob->dataset(BlobVector::kTouched) + "' of configuration " +
                       std::to_string(c.id.value()) + " is not an ascending list of node ids");
    }
    touched.push_back(static_cast<int>(n));
  }
  return touched;
}

ConfigVectors load_config_vectors(const BlobStore& blobs, const Configuration& c,
                                  const std::vector<double>& rest_u, const VectorLayout& layout) {
  const int num_dofs = static_cast<int>(rest_u.size());
  ConfigVectors v;
  if (!c.blob) {
    v.u = rest_u;
    v.t.assign(layout.t_size(0), 0.0);
    v.h.assign(layout.h_size(0), 0.0);
    return v;
  }
  v.u = blobs.read(c.blob->segment, c.blob->dataset(BlobVector::kU));
  v.t = blobs.read(c.blob->segment, c.blob->dataset(BlobVector::kT));
  v.h = blobs.read(c.blob->segment, c.blob->dataset(BlobVector::kH));
  if (layout.touched) v.touched = read_touched_set(blobs, c, num_dofs / 3);
  if (layout.multipliers)
    v.multipliers = blobs.read(c.blob->segment, c.blob->dataset(BlobVector::kMultipliers));
  const int num_reactions = layout.h_size(v.touched.size());
  if (static_cast<int>(v.u.size()) != num_dofs || static_cast<int>(v.h.size()) != num_reactions) {
    throw InputError((blobs.directory() / segment_file_name(c.blob->segment)).string() +
                     ": vectors of configuration " + std::to_string(c.id.value()) + " ('" +
                     c.blob->name + "') have " + std::to_string(v.u.size()) + " / " +
                     std::to_string(v.h.size()) + " values, the problem needs " +
                     std::to_string(num_dofs) + " / " + std::to_string(num_reactions));
  }
  return v;
}

ConfigVectors load_level_vectors(const BlobStore& blobs, const Configuration& c,
                                 const std::vector<double>& rest_u) {
  ConfigVectors v;
  if (!c.blob) {
    v.u = rest_u;  // the zero configuration: the loaded rest state (empty: u = 0)
    return v;
  }
  v.u = blobs.read(c.blob->segment, c.blob->dataset(BlobVector::kU));
  v.h = blobs.read(c.blob->segment, c.blob->dataset(BlobVector::kH));
  // Sticking contact: the touched set is part of the configuration (never merge different sets).
  if (blobs.contains(c.blob->segment, c.blob->dataset(BlobVector::kTouched)))
    v.touched = read_touched_set(blobs, c, static_cast<int>(v.u.size() / 3));
  return v;
}

void write_config_vectors(SegmentWriter& writer, const BlobRef& blob, const ConfigVectors& v,
                          std::span<const float> du_dp, const VectorLayout& layout) {
  writer.write(blob.dataset(BlobVector::kU), v.u);
  writer.write(blob.dataset(BlobVector::kT), v.t);
  writer.write(blob.dataset(BlobVector::kH), v.h);
  if (!du_dp.empty()) writer.write(blob.dataset(BlobVector::kDuDp), du_dp);
  if (layout.multipliers) writer.write(blob.dataset(BlobVector::kMultipliers), v.multipliers);
  if (layout.touched)
    writer.write(blob.dataset(BlobVector::kTouched), std::span<const int>(v.touched));
}

void write_midpoint_vectors(SegmentWriter& writer, const BlobRef& blob, std::span<const float> u,
                            std::span<const float> du_dp) {
  writer.write(blob.dataset(BlobVector::kU), u);
  writer.write(blob.dataset(BlobVector::kDuDp), du_dp);
}

}  // namespace hapstate
