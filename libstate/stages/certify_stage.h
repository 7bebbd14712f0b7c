// The certify stage (hapstate-certify, docs/certificate.md): the paper's experiment, the precise
// solver against the haptic cursors, on N seeded random paths over the whole workspace (a
// contact probe's paths are pulled toward the body: onsets, sliding and leaving), in parallel
// and resumable; then the haptic query's time along them and the largest stored stiffness. What
// it measured goes to the catalogue (tables certificate_path, certificate_step, certificate)
// and its headline numbers into the playback file, so a haptic application reads what it was
// promised (hapstate::PlaybackFile::certificate()).
#pragma once

#include "maintenance/certificate_report.h"
#include "statedir/stage_run.h"

#include <cstdio>
#include <filesystem>
#include <string>

namespace hapstate {

struct CertifyOptions {
  std::filesystem::path state;
  int paths = 0;    // 0: the scene's certify.paths (default 20)
  int steps = 0;    // 0: the scene's certify.steps (default 30)
  int threads = 1;  // worker threads, each with its own precise solver
  // The two-sided solves (eval/equilibria.h): at the Hermite and the trilinear cursor's worst
  // step, where its force error is above this fraction of its path's largest force, the precise
  // solver reaches the position from half a spacing before and after on each axis, telling a
  // jump of the force (two equilibria) from a steep ramp.
  double check_above = 0.01;
  std::FILE* progress = stderr;

  // Throws InputError naming the first bad option (run_certify calls it first).
  void check() const;
};

// outcome: kOk, kPartial (stopped by Ctrl-C / SIGTERM: run again to finish) or kUnchanged
// (the certificate was complete and current: nothing done).
struct CertifyReport : StageReport {
  int paths = 0, steps = 0;  // asked for
  int solved_now = 0;        // paths measured by this run
  int checked_now = 0;       // worst steps given two-sided solves by this run
  std::int64_t stale_deleted = 0;
  Certificate certificate;
};

// Needs a playback file built from the state directory (hapstate-index). Records a "certify"
// stage run. Throws InputError naming the file or option when the state or the playback file is
// unusable.
CertifyReport run_certify(const CertifyOptions& options);

}  // namespace hapstate
