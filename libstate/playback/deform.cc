// Blending the corner displacement arrays of a snapshot into view-node positions (visual thread).
#include "playback/file_impl.h"

#include <algorithm>

namespace hapstate {
namespace {

// out = Σ w_c u_c over the distinct corner configurations with a non-zero weight.
void blend(const PlaybackFile& file, const Snapshot& s, std::span<float> out) {
  const PlaybackFile::Impl& f = file.impl();
  const std::size_t n = 3 * static_cast<std::size_t>(f.meta->num_view_nodes);
  std::int32_t config[8];
  float weight[8];
  int count = 0;
  for (int c = 0; c < 8; ++c) {
    const std::int32_t k = s.corner_configuration[c];
    if (k < 0 || k >= f.meta->num_configurations || s.weight[c] == 0.0) continue;
    int j = 0;
    while (j < count && config[j] != k) ++j;
    if (j == count) config[count] = k, weight[count++] = 0.0f;
    weight[j] += static_cast<float>(s.weight[c]);
  }
  float* o = out.data();
  const std::size_t m = std::min(n, out.size());
  for (int j = 0; j < count; ++j) {
    const float* u = f.displacements + n * static_cast<std::size_t>(config[j]);
    const float w = weight[j];
    for (std::size_t i = 0; i < m; ++i) o[i] += w * u[i];
  }
}

}  // namespace

void displacements(const PlaybackFile& file, const Snapshot& snapshot, std::span<float> out) {
  std::fill(out.begin(), out.end(), 0.0f);
  blend(file, snapshot, out);
}

void deform(const PlaybackFile& file, const Snapshot& snapshot, std::span<float> out) {
  const auto ref = file.reference_positions();
  std::copy_n(ref.begin(), std::min(ref.size(), out.size()), out.begin());
  blend(file, snapshot, out);
}

}  // namespace hapstate
