#include "maintenance/state_paths.h"

#include "blobs/segment.h"
#include "util/error.h"

namespace hapstate {
namespace {

std::int64_t size_or_zero(const std::filesystem::path& file) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(file, ec);
  return ec ? 0 : static_cast<std::int64_t>(size);
}

}  // namespace

StateDir locate_state(const std::filesystem::path& root) {
  std::error_code ec;
  if (!std::filesystem::is_directory(root, ec)) {
    throw InputError(root.string() + ": no such state directory");
  }
  StateDir dir{root};
  if (!std::filesystem::exists(dir.catalogue(), ec)) {
    throw InputError(root.string() + ": not a state directory (no " +
                     dir.catalogue().filename().string() + "; hapstate-import creates it)");
  }
  return dir;
}

DiskUse measure_disk_use(const StateDir& dir) {
  DiskUse use;
  // Not "-shm": SQLite's shared-memory index of the WAL, rebuilt by any reader; counting it
  // made the same catalogue measure differently after a read.
  for (const char* suffix : {"", "-wal"}) {
    use.catalogue_bytes += size_or_zero(dir.catalogue().string() + suffix);
  }
  std::error_code ec;
  if (std::filesystem::is_directory(dir.problem(), ec)) {
    for (const auto& entry : std::filesystem::directory_iterator(dir.problem(), ec)) {
      if (entry.is_regular_file(ec)) use.problem_bytes += size_or_zero(entry.path());
    }
  }
  if (!std::filesystem::is_directory(dir.blobs(), ec)) return use;
  for (const auto& entry : std::filesystem::directory_iterator(dir.blobs(), ec)) {
    if (!entry.is_regular_file(ec)) continue;
    if (!parse_segment_file_name(entry.path().filename().string())) continue;
    use.blob_bytes += size_or_zero(entry.path());
    ++use.segments;
  }
  return use;
}

}  // namespace hapstate
