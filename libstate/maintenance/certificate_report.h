// The certificate of a state directory (docs/certificate.md) summarised from what
// hapstate-certify stored: per scheme the worst and 99th-percentile force error (relative to
// the path's largest force, and in N) and deformation error, what the paths covered (contact
// steps, onsets, leavings), the largest stored stiffness against common haptic devices, the
// haptic query's time, where the worst errors are, and whether it still describes the playback
// file (stale when that file was rebuilt since, or when the playback code that measured it
// changed). Every statistic is over the measured steps themselves: never less than a step
// measured.
#pragma once

#include "catalogue/records.h"

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace hapstate {

struct SchemeCertificate {
  double worst = 0, p99 = 0;                          // |f - f*| / the path's max |f*|
  double worst_n = 0, p99_n = 0;                      // |f - f*|, N
  double deformation_worst = 0, deformation_p99 = 0;  // surface, contact onsets left out
};

struct CertificateLocation {
  int scheme = 0;  // 0 trilinear, 1 Hermite
  int seed = 0, step = 0;
  std::array<double, 3> probe{};
  std::array<int, 3> cell{}, checkpoint{};
  double error = 0, error_n = 0;
};

// A common haptic device's nominal stiffness (its weakest axis), N/mm: the stiffest virtual
// spring it renders stably.
struct DeviceLimit {
  const char* name;
  double n_per_mm;
};
extern const std::array<DeviceLimit, 4> kDeviceLimits;

struct Certificate {
  bool present = false;   // some path is stored
  bool complete = false;  // a run ended: timing and stiffness measured
  bool stale = true;      // measured on another playback file or by other playback code (or none)
  ContentHash playback_hash;  // certified_hash() of what it was measured on
  int paths = 0, steps_per_path = 0;
  int steps = 0, failed_steps = 0;
  bool contact = false;  // a contact probe: the steps touching, their onsets and leavings
  int contact_steps = 0, onsets = 0, leavings = 0;
  std::array<SchemeCertificate, 2> schemes{};  // trilinear, Hermite
  double stiffness_n_per_mm = 0;
  std::int64_t queries = 0;
  double query_median_ns = 0, query_p999_ns = 0;
  std::vector<CertificateLocation> worst;  // the largest force errors, per scheme, largest first
  // The two-sided solves hapstate-certify made at its worst steps (of this playback file), by
  // seed, step, axis: whether the force jumps there (docs/certificate.md).
  std::vector<CertificateEquilibria> equilibria;
};

// What a certificate is measured on: the playback file (its source hash) played back by this
// build's playback code (playback_code_id(), playback/code_id.h). Either changing makes it stale.
ContentHash certified_hash(std::uint64_t playback_source_hash);

// `current`: certified_hash() of the playback file the state has now (nullopt: none); `contact`:
// its probe is a contact sphere (a step touches where its precise force is not zero).
Certificate summarise_certificate(const std::vector<CertificatePath>& paths,
                                  const std::vector<CertificateEquilibria>& equilibria,
                                  const std::optional<CertificateRun>& run,
                                  const std::optional<ContentHash>& current, bool contact,
                                  int worst_per_scheme = 5);

// The report: `json` an object for `hapstate-inspect summary --json`'s "certificate" key (one
// line of JSON, or "null" without a certificate), `text` lines for a terminal.
struct CertificateText {
  std::string json;
  std::string text;
  std::string headline;  // one line: the worst force error of each scheme
};
CertificateText certificate_text(const Certificate& c);

}  // namespace hapstate
