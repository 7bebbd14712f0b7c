// The disk fills during hapstate-expand (issue 15): a real, size-limited tmpfs in a private
// mount namespace of this test process (root, as in CI), else writes made to fail with ENOSPC
// by a test-only LD_PRELOAD shim (enospc_shim.c; HAPSTATE_DISK_FULL=shim forces it). Either the
// blob segments' file system fills (the HDF5 write fails) or the catalogue's (the SQLite commit
// fails). Each time: exit 4 (I/O or environment failure, docs/exit-codes.md), stderr names the file
// and the OS or library error; nothing stored is corrupted (SQLite integrity, foreign keys, every
// stored vector readable, the rows an exact prefix of an uninterrupted run's: complete batches
// only); with space again the next run resumes and ends with the same catalogue as an uninterrupted
// run.
#include "beam_state.h"

#include "blobs/blob_store.h"
#include "catalogue/catalogue.h"
#include "maintenance/inspect.h"

#include <sched.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <sys/statvfs.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <map>
#include <optional>
#include <string>

namespace hapstate::test_util {
namespace {

// Once per process: a mount namespace of our own with private propagation, so the tmpfs mounts
// below are seen by this process and the stages it starts only, and vanish with the process
// even if it crashes. Empty on success, else why not (not root, no CAP_SYS_ADMIN, seccomp).
const std::string& private_mount_namespace() {
  static const std::string why = []() -> std::string {
    if (::unshare(CLONE_NEWNS) != 0)
      return std::string("unshare(CLONE_NEWNS): ") + std::strerror(errno);
    if (::mount(nullptr, "/", nullptr, MS_REC | MS_PRIVATE, nullptr) != 0)
      return std::string("mount --make-rprivate /: ") + std::strerror(errno);
    return "";
  }();
  return why;
}

constexpr std::uint64_t kPage = 4096;
constexpr std::uint64_t kMiB = 1024 * 1024;

std::uint64_t round_up(std::uint64_t bytes) { return (bytes + kPage - 1) / kPage * kPage; }

// A tmpfs of a given size mounted at a directory (created) until destroyed.
class Tmpfs {
 public:
  Tmpfs(fs::path where, std::uint64_t bytes) : where_(std::move(where)) {
    fs::create_directories(where_);
    const std::string options = "size=" + std::to_string(round_up(bytes)) + ",mode=0755";
    if (::mount("tmpfs", where_.c_str(), "tmpfs", MS_NOSUID | MS_NODEV, options.c_str()) != 0) {
      why_ = "mount -t tmpfs -o " + options + " " + where_.string() + ": " + std::strerror(errno);
      return;
    }
    mounted_ = true;
  }
  ~Tmpfs() {
    if (mounted_) ::umount2(where_.c_str(), MNT_DETACH);
  }
  Tmpfs(const Tmpfs&) = delete;
  Tmpfs& operator=(const Tmpfs&) = delete;

  bool mounted() const { return mounted_; }
  const std::string& why() const { return why_; }
  // A new size (tmpfs refuses one below what is in use).
  void resize(std::uint64_t bytes) {
    const std::string options = "size=" + std::to_string(round_up(bytes));
    ASSERT_EQ(::mount("tmpfs", where_.c_str(), "tmpfs", MS_REMOUNT | MS_NOSUID | MS_NODEV,
                      options.c_str()),
              0)
        << "remount " << where_ << " " << options << ": " << std::strerror(errno);
  }
  std::uint64_t used() const {
    struct statvfs s {};
    EXPECT_EQ(::statvfs(where_.c_str(), &s), 0);
    return (s.f_blocks - s.f_bfree) * s.f_frsize;
  }
  std::uint64_t available() const {
    struct statvfs s {};
    EXPECT_EQ(::statvfs(where_.c_str(), &s), 0);
    return s.f_bavail * s.f_frsize;
  }

 private:
  fs::path where_;
  bool mounted_ = false;
  std::string why_;
};

// Bytes the files under `dir` occupy (allocated blocks).
std::uint64_t allocated_bytes(const fs::path& dir) {
  std::uint64_t total = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    struct stat st {};
    if (e.is_regular_file() && ::stat(e.path().c_str(), &st) == 0)
      total += std::uint64_t(st.st_blocks) * 512;
  }
  return total;
}

#if defined(__SANITIZE_ADDRESS__)
constexpr bool kSanitized = true;  // the ASan runtime must come first: no LD_PRELOAD shim
#else
constexpr bool kSanitized = false;
#endif

class DiskFull : public StageTest {
 protected:
  void SetUp() override {
    StageTest::SetUp();
    // A real file system if we may mount one; else (or with HAPSTATE_DISK_FULL=shim) the
    // test-only LD_PRELOAD shim (tests/stages/enospc_shim.c) fails the stage's writes with
    // ENOSPC once a byte budget is spent.
    const char* mode = std::getenv("HAPSTATE_DISK_FULL");
    const std::string why = mode != nullptr && std::string(mode) == "shim"
                                ? std::string("HAPSTATE_DISK_FULL=shim")
                                : private_mount_namespace();
    tmpfs_ = why.empty();
    if (!tmpfs_ && kSanitized)
      GTEST_SKIP() << "no size-limited file system can be mounted here (" << why
                   << ") and the LD_PRELOAD shim cannot run under AddressSanitizer: the "
                      "full-disk test needs root (CAP_SYS_ADMIN) for a private tmpfs";
    if (!tmpfs_)
      std::printf("[ info ] no tmpfs (%s): injected ENOSPC through the LD_PRELOAD shim\n",
                  why.c_str());
    // The uninterrupted run every case is compared with (on the ordinary temporary disk).
    reference_ = dir_ / "reference";
    build_beam(reference_, kBeamScene, 1, dir_);
    ASSERT_FALSE(HasFatalFailure());
    reference_snapshot_ = snapshot(reference_);
  }

  // After a failed run: SQLite finds nothing wrong, every stored configuration's vectors read
  // back, and the rows are exactly those of the uninterrupted run's first batches (every
  // configuration and transition stored equals the reference's of the same id / key).
  // Returns how many configurations and transitions are stored.
  std::pair<std::size_t, std::size_t> expect_intact_prefix(const fs::path& state) {
    const Snapshot s = snapshot(state);
    {
      Catalogue cat(state / "catalogue.sqlite", OpenMode::kReadOnly);
      EXPECT_EQ(cat.integrity_check(), "ok");
      EXPECT_EQ(cat.num_foreign_key_violations(), 0);
    }
    BlobStore blobs(state / "blobs");
    std::map<std::int64_t, const Configuration*> reference_configs;
    for (const Configuration& c : reference_snapshot_.configurations)
      reference_configs[c.id.value()] = &c;
    for (const Configuration& c : s.configurations) {
      const auto it = reference_configs.find(c.id.value());
      if (it == reference_configs.end()) {
        ADD_FAILURE() << "configuration " << c.id.value() << " is not in the uninterrupted run";
        continue;
      }
      const Configuration& r = *it->second;
      EXPECT_EQ(c.checkpoint, r.checkpoint) << "configuration " << c.id.value();
      EXPECT_EQ(c.level, r.level) << "configuration " << c.id.value();
      EXPECT_EQ(c.blob, r.blob) << "configuration " << c.id.value();
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(c.force[k], r.force[k], 1e-12 * (1 + std::abs(r.force[k])));
      if (!c.blob) continue;
      for (const char* v : {"/u", "/t", "/h"}) {
        try {
          const auto x = blobs.read(c.blob->segment, c.blob->name + v);
          EXPECT_FALSE(x.empty()) << c.blob->name << v;
        } catch (const std::exception& e) {
          ADD_FAILURE() << "configuration " << c.id.value() << ": " << e.what();
        }
      }
    }
    std::map<std::pair<std::int64_t, int>, const Transition*> reference_transitions;
    for (const Transition& t : reference_snapshot_.transitions)
      reference_transitions[{t.source.value(), t.direction.index()}] = &t;
    for (const Transition& t : s.transitions) {
      const auto it = reference_transitions.find({t.source.value(), t.direction.index()});
      if (it == reference_transitions.end()) {
        ADD_FAILURE() << "transition " << t.source.value() << "/" << t.direction.index()
                      << " is not in the uninterrupted run";
        continue;
      }
      EXPECT_EQ(t.outcome, it->second->outcome);
      EXPECT_EQ(t.target, it->second->target);
    }
    // hapstate-inspect's summary reads the whole directory.
    try {
      const InspectOutput summary = inspect_summary(StateDir{state});
      EXPECT_NE(summary.text.find("expand"), std::string::npos) << summary.text;
    } catch (const std::exception& e) {
      ADD_FAILURE() << "hapstate-inspect summary: " << e.what();
    }
    return {s.configurations.size(), s.transitions.size()};
  }

  // hapstate-expand on `state` with a disk that is full once `bytes` more are written to the
  // files directly in `dir`: with tmpfs, the caller has mounted it with that much room; with
  // the shim, the budget is given to it here.
  StageResult expand_on_full_disk(const fs::path& state, const fs::path& dir, std::uint64_t bytes) {
    return tmpfs_ ? expand_stage(state, 1, dir_) : expand_with_shim(state, dir, bytes, ENOSPC);
  }
  // hapstate-expand on `state` under the shim: writes to the files directly in `dir` fail with
  // `error` once `bytes` were written there.
  StageResult expand_with_shim(const fs::path& state, const fs::path& dir, std::uint64_t bytes,
                               int error) {
    ::setenv("LD_PRELOAD", HAPSTATE_ENOSPC_SHIM, 1);
    ::setenv("HAPSTATE_ENOSPC_DIR", fs::weakly_canonical(dir).c_str(), 1);
    ::setenv("HAPSTATE_ENOSPC_BYTES", std::to_string(bytes).c_str(), 1);
    ::setenv("HAPSTATE_ENOSPC_ERRNO", std::to_string(error).c_str(), 1);
    StageResult r = expand_stage(state, 1, dir_);
    for (const char* name :
         {"LD_PRELOAD", "HAPSTATE_ENOSPC_DIR", "HAPSTATE_ENOSPC_BYTES", "HAPSTATE_ENOSPC_ERRNO"})
      ::unsetenv(name);
    return r;
  }

  bool tmpfs_ = false;  // a real size-limited tmpfs, else the shim
  fs::path reference_;
  Snapshot reference_snapshot_;
};

// The blobs/ directory is a tmpfs holding about half of what the whole run's segments need:
// writing a segment (HDF5) fails with ENOSPC part-way through the expansion.
TEST_F(DiskFull, SegmentWriteOnAFullDiskIsExit4AndResumes) {
  const fs::path state = dir_ / "state";
  ASSERT_EQ(import_stage(state, kBeamScene, dir_).exit_code, 0);
  ASSERT_EQ(grid_stage(state, dir_).exit_code, 0);
  const std::size_t configs_before = snapshot(state).configurations.size();

  const std::uint64_t needed = allocated_bytes(reference_ / "blobs");
  ASSERT_GE(needed, 8 * kPage) << "the beam's segments are too small to fill a disk part-way";
  // Half the run, off a page boundary of the segments (the disk fills inside one).
  const std::uint64_t limit = needed / 2 + 3 * kPage;
  std::optional<Tmpfs> blobs;
  if (tmpfs_) {
    blobs.emplace(state / "blobs", limit);
    ASSERT_TRUE(blobs->mounted()) << blobs->why();
  }

  const StageResult full = expand_on_full_disk(state, state / "blobs", limit);
  EXPECT_EQ(full.exit_code, 4) << full.err;
  EXPECT_NE(full.err.find("hapstate-expand: error: "), std::string::npos) << full.err;
  EXPECT_NE(full.err.find((state / "blobs" / "seg-").string()), std::string::npos)
      << "names the segment file: " << full.err;
  EXPECT_NE(full.err.find("No space left on device"), std::string::npos) << full.err;
  EXPECT_EQ(std::count(full.err.begin(), full.err.end(), '\n'), 1)
      << "one message, nothing else: " << full.err;
  std::printf("[ info ] blobs %s of %llu KiB (the whole run needs %llu KiB); stderr: %s",
              tmpfs_ ? "tmpfs" : "write budget",
              static_cast<unsigned long long>(round_up(limit) / 1024),
              static_cast<unsigned long long>(needed / 1024), full.err.c_str());

  // Nothing corrupted, complete batches only; the failed segment was removed by its writer.
  const auto [configs, transitions] = expect_intact_prefix(state);
  EXPECT_GT(configs, configs_before) << "the disk filled before the first batch was stored";
  EXPECT_LT(configs, reference_snapshot_.configurations.size());
  {
    Catalogue cat(state / "catalogue.sqlite", OpenMode::kReadOnly);
    EXPECT_TRUE(
        BlobStore(state / "blobs").unreferenced_segments(cat.referenced_segments()).empty());
    const StageRun run = cat.read_stage_runs("expand").back();
    EXPECT_EQ(run.outcome, StageOutcome::kFailed);
    EXPECT_NE(run.message.find("No space left on device"), std::string::npos) << run.message;
  }
  std::printf(
      "[ info ] stored when the disk was full: %zu of %zu configurations, %zu of %zu "
      "transitions\n",
      configs, reference_snapshot_.configurations.size(), transitions,
      reference_snapshot_.transitions.size());

  // Space again: the same command resumes and completes.
  if (blobs) blobs->resize(4 * needed + 4 * kMiB);
  ASSERT_FALSE(HasFatalFailure());
  const StageResult resumed = expand_stage(state, 1, dir_);
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  expect_same_catalogue(reference_, state);
}

// The state directory (catalogue.sqlite and its WAL) is a tmpfs with little room left after the
// grid; blobs/ is a roomy tmpfs of its own: the SQLite commit of a batch fails with "database or
// disk is full" part-way through, after its segment was written. Several amounts of room are
// tried until the failed batch is one that made new configurations (most later batches only
// reach stored ones and write no segment), so that its orphan segment is seen and removed.
class CatalogueFull : public DiskFull {
 protected:
  // One attempt in dir_/<name> with `room` bytes free for the run; returns the number of
  // unreferenced segments the failure left (0 or 1).
  std::size_t fill_and_resume(const std::string& name, std::uint64_t room) {
    const fs::path state = dir_ / name;
    std::optional<Tmpfs> disk, blobs;
    if (tmpfs_) {
      disk.emplace(state, 64 * kMiB);
      EXPECT_TRUE(disk->mounted()) << disk->why();
      if (!disk->mounted()) return 0;
    }
    EXPECT_EQ(import_stage(state, kBeamScene, dir_).exit_code, 0);
    EXPECT_EQ(grid_stage(state, dir_).exit_code, 0);
    const std::size_t configs_before = snapshot(state).configurations.size();
    if (tmpfs_) {
      blobs.emplace(state / "blobs", 64 * kMiB);
      EXPECT_TRUE(blobs->mounted()) << blobs->why();
      disk->resize(disk->used() + room);
    }
    if (HasFailure()) return 0;

    const StageResult full = expand_on_full_disk(state, state, room);
    EXPECT_EQ(full.exit_code, 4) << full.err;
    EXPECT_NE(full.err.find("hapstate-expand: error: " + (state / "catalogue.sqlite").string()),
              std::string::npos)
        << "names the catalogue: " << full.err;
    EXPECT_NE(full.err.find("database or disk is full"), std::string::npos) << full.err;
    EXPECT_EQ(std::count(full.err.begin(), full.err.end(), '\n'), 1) << "one message: " << full.err;
    std::printf("[ info ] %llu KiB left for the catalogue; stderr: %s",
                static_cast<unsigned long long>(room / 1024), full.err.c_str());

    // Nothing corrupted, complete batches only; the failed batch's segment, if it wrote one,
    // was closed before its transaction and is referenced by nothing.
    const auto [configs, transitions] = expect_intact_prefix(state);
    EXPECT_GT(configs, configs_before) << "the disk filled before the first batch was stored";
    EXPECT_LT(transitions, reference_snapshot_.transitions.size());
    std::size_t orphans = 0;
    {
      Catalogue cat(state / "catalogue.sqlite", OpenMode::kReadOnly);
      orphans = BlobStore(state / "blobs").unreferenced_segments(cat.referenced_segments()).size();
      EXPECT_LE(orphans, 1u);
    }
    std::printf(
        "[ info ] stored when the disk was full: %zu of %zu configurations, %zu of %zu "
        "transitions; %zu unreferenced segment(s)\n",
        configs, reference_snapshot_.configurations.size(), transitions,
        reference_snapshot_.transitions.size(), orphans);

    // Space again: the same command removes the orphan segment, resumes and completes.
    if (disk) disk->resize(64 * kMiB);
    const StageResult resumed = expand_stage(state, 1, dir_);
    EXPECT_EQ(resumed.exit_code, 0) << resumed.err;
    if (orphans == 1) {
      EXPECT_NE(resumed.err.find("removed 1 unreferenced segment"), std::string::npos)
          << resumed.err;
    }
    expect_same_catalogue(reference_, state);
    return orphans;
  }
};

TEST_F(CatalogueFull, CatalogueCommitOnAFullDiskIsExit4AndResumes) {
  // 32 KiB for the WAL index, the rest for the write-ahead log: a few batches (each commit
  // appends the pages it changed, 4 KiB each; the whole run's WAL stays below SQLite's
  // 1000-page checkpoint and grows to megabytes), not the whole run.
  std::size_t orphans = 0;
  int attempt = 0;
  for (std::uint64_t log_kib : {256, 224, 192, 160}) {
    orphans = fill_and_resume("state" + std::to_string(attempt++), (32 + log_kib) * 1024);
    if (HasFailure() || orphans == 1) break;
  }
  EXPECT_EQ(orphans, 1u) << "no attempt failed in a batch that wrote a segment";
}

// An I/O error (EIO, injected by the shim: no real file system fails on demand) while writing a
// segment or the catalogue is exit 4 too, naming the file and the OS error (HDF5) or the failed
// operation (SQLite); the next run completes with the same catalogue.
TEST_F(DiskFull, IoErrorsAreExit4NamingTheOsError) {
  if (kSanitized) GTEST_SKIP() << "the LD_PRELOAD shim cannot run under AddressSanitizer";
  const std::uint64_t needed = allocated_bytes(reference_ / "blobs");
  for (const bool segment : {true, false}) {
    const fs::path state = dir_ / (segment ? "segment" : "catalogue");
    ASSERT_EQ(import_stage(state, kBeamScene, dir_).exit_code, 0);
    ASSERT_EQ(grid_stage(state, dir_).exit_code, 0);
    const StageResult failed = segment ? expand_with_shim(state, state / "blobs", needed / 2, EIO)
                                       : expand_with_shim(state, state, 256 * 1024, EIO);
    EXPECT_EQ(failed.exit_code, 4) << failed.err;
    EXPECT_EQ(std::count(failed.err.begin(), failed.err.end(), '\n'), 1) << failed.err;
    if (segment) {
      EXPECT_NE(failed.err.find((state / "blobs" / "seg-").string()), std::string::npos)
          << failed.err;
      EXPECT_NE(failed.err.find(": Input/output error (HDF5: file write failed)"),
                std::string::npos)
          << failed.err;
    } else {
      EXPECT_NE(failed.err.find((state / "catalogue.sqlite").string() + ": SQLite error in "),
                std::string::npos)
          << failed.err;
      EXPECT_NE(failed.err.find("disk I/O error (write failed, SQLITE_IOERR_WRITE)"),
                std::string::npos)
          << failed.err;
    }
    std::printf("[ info ] EIO: %s", failed.err.c_str());
    expect_intact_prefix(state);
    const StageResult resumed = expand_stage(state, 1, dir_);
    ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
    expect_same_catalogue(reference_, state);
  }
}

}  // namespace
}  // namespace hapstate::test_util
