// Stored bytes per configuration against the vectors' own size (docs/benchmarks.md, "Stored bytes
// per configuration"): for a state directory, the blob segments' bytes on disk per configuration
// beside the raw bytes of its vectors (in their stored types) and those bytes compressed by zstd
// alone, one configuration at a time, at the level the segments use (what a perfect container would
// take). A transition's midpoint vectors (groups m<source>_<direction>) count with the
// configurations: per configuration is per configuration group, midpoints included. Usage:
// storage_bench STATE_DIR
#include "blobs/blob_store.h"
#include "blobs/zstd_filter.h"

#include <zstd.h>

#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  using namespace hapstate;
  if (argc != 2) {
    std::fprintf(stderr, "usage: storage_bench STATE_DIR\n");
    return 2;
  }
  const std::filesystem::path blobs_dir = std::filesystem::path(argv[1]) / "blobs";
  try {
    BlobStore blobs(blobs_dir);
    long long configurations = 0, midpoints = 0, raw = 0, compressed = 0, on_disk = 0;
    std::map<std::string, long long> raw_by_leaf;
    for (SegmentId id : blobs.list_segments()) {
      on_disk +=
          static_cast<long long>(std::filesystem::file_size(blobs_dir / segment_file_name(id)));
      std::map<std::string, std::vector<char>> groups;  // a configuration's vectors, concatenated
      for (const std::string& name : blobs.list_vectors(id)) {
        const std::string group = name.substr(0, name.rfind('/'));
        std::vector<char>& bytes = groups[group];
        const auto append = [&](const void* p, std::size_t n) {
          bytes.insert(bytes.end(), static_cast<const char*>(p), static_cast<const char*>(p) + n);
        };
        const Precision precision = blobs.precision_of(id, name);
        const std::vector<double> values = blobs.read(id, name);
        if (precision == Precision::kFloat64) append(values.data(), 8 * values.size());
        if (precision == Precision::kFloat32) {
          const std::vector<float> f = blobs.read_float32(id, name);
          append(f.data(), 4 * f.size());
        }
        if (precision == Precision::kInt32) {
          const std::vector<int> ints(values.begin(), values.end());
          append(ints.data(), 4 * ints.size());
        }
        raw_by_leaf[name.substr(name.rfind('/') + 1)] +=
            static_cast<long long>(values.size() * (precision == Precision::kFloat64 ? 8 : 4));
      }
      for (const auto& [group, bytes] : groups) {
        std::vector<char> out(ZSTD_compressBound(bytes.size()));
        const std::size_t n =
            ZSTD_compress(out.data(), out.size(), bytes.data(), bytes.size(), kDefaultZstdLevel);
        if (ZSTD_isError(n)) throw std::runtime_error(ZSTD_getErrorName(n));
        ++(group[0] == 'm' ? midpoints : configurations);
        raw += static_cast<long long>(bytes.size());
        compressed += static_cast<long long>(n);
      }
    }
    if (configurations == 0)
      throw std::runtime_error(blobs_dir.string() + ": no stored configurations");
    const double c = static_cast<double>(configurations);
    std::printf("%s: %lld configurations and %lld midpoints in blobs\n", argv[1], configurations,
                midpoints);
    std::printf("  on disk            %10.0f bytes per configuration\n", on_disk / c);
    std::printf("  raw vectors        %10.0f bytes per configuration (", raw / c);
    for (const auto& [leaf, bytes] : raw_by_leaf) std::printf(" %s %.0f", leaf.c_str(), bytes / c);
    std::printf(" )\n  zstd of the raw    %10.0f bytes per configuration (level %d, each alone)\n",
                compressed / c, kDefaultZstdLevel);
    std::printf("  on disk / zstd     %10.2f\n", on_disk / static_cast<double>(compressed));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "storage_bench: %s\n", e.what());
    return 1;
  }
  return 0;
}
