#include "maintenance/certificate_report.h"

#include "maintenance/inspect_common.hpp"
#include "playback/code_id.h"
#include "playback/scheme_name.h"
#include "util/distribution.h"
#include "util/paper_bounds.h"
#include "util/text.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

namespace hapstate {

using inspect_detail::Json;

// Manufacturers' nominal stiffness, the weakest axis (datasheets): 3D Systems Touch (formerly
// Phantom Omni) x 1.26, y 2.31, z 1.02 N/mm; Touch X x 1.86, y 2.35, z 1.48 N/mm; Phantom Premium
// 1.5 3.5 N/mm; Force Dimension omega.3 14.5 N/mm.
const std::array<DeviceLimit, 4> kDeviceLimits = {{{"3D Systems Touch", 1.02},
                                                   {"3D Systems Touch X", 1.48},
                                                   {"Phantom Premium 1.5", 3.5},
                                                   {"Force Dimension omega.3", 14.5}}};

namespace {

constexpr const char* kSchemeTitles[2] = {"trilinear", "Hermite"};

// Worst and 99th percentile (nearest rank) of a sample; zeros for an empty one.
std::pair<double, double> worst_p99(std::vector<double> v) {
  const Distribution d = summarize(v);
  return {d.max, d.p99};
}

// |f- - f+| of a two-sided solve, N; NaN unless both approaches converged.
double difference(const CertificateEquilibria& e) {
  if (!e.force_minus || !e.force_plus) return std::numeric_limits<double>::quiet_NaN();
  double s = 0;
  for (int a = 0; a < 3; ++a) s += std::pow((*e.force_minus)[a] - (*e.force_plus)[a], 2);
  return std::sqrt(s);
}

double magnitude(const std::optional<std::array<double, 3>>& f) {
  return f ? std::sqrt((*f)[0] * (*f)[0] + (*f)[1] * (*f)[1] + (*f)[2] * (*f)[2]) : 0.0;
}

// The two-sided solves of one step, a line per axis and what they mean together; `whose`: the
// cursors it is the worst step of ("" when not among c.worst).
void equilibria_lines(std::ostringstream& t, const std::vector<CertificateEquilibria>& rows,
                      const std::string& whose) {
  char line[400];
  std::snprintf(line, sizeof line,
                "  two-sided solves at seed %d step %d%s (the precise solver reaching it from half "
                "a spacing before and after, on each axis):\n",
                rows.front().seed, rows.front().step, whose.c_str());
  t << line;
  bool two = false, ends = false, undecided = false;
  for (const CertificateEquilibria& e : rows) {
    const char axis = "xyz"[e.axis];
    if (e.verdict == Equilibria::kTwo) {
      two = true;
      const double d = difference(e);
      const double larger = std::max(magnitude(e.force_minus), magnitude(e.force_plus));
      std::snprintf(line, sizeof line,
                    "    %c: two equilibria, the forces %s N apart (%s of the larger)\n", axis,
                    sci(d).c_str(), percent(larger > 0 ? d / larger : 0.0).c_str());
    } else if (e.verdict == Equilibria::kEnds) {
      ends = true;
      std::snprintf(line, sizeof line,
                    "    %c: Newton failed from %s only: likely an equilibrium ending here\n", axis,
                    e.force_minus ? "+along" : "-along");
    } else if (e.verdict == Equilibria::kOne) {
      std::snprintf(line, sizeof line, "    %c: one equilibrium\n", axis);
    } else {
      undecided = true;
      std::snprintf(line, sizeof line, "    %c: not decided (an approach failed)\n", axis);
    }
    t << line;
  }
  if (two || ends)
    t << "    => the force jumps here (the surface slides off the probe to one side or the "
         "other): no grid spacing or refinement depth removes this error; a larger instrument "
         "or a surface smooth at the instrument's scale may (docs/certificate.md, \"When it is "
         "not good enough\")\n";
  else if (!undecided)
    t << "    => no jump here: the error is the interpolation's (a steep ramp or a kink of the "
         "force), which a smaller grid spacing or a deeper refinement brings down "
         "(docs/certificate.md, \"When it is not good enough\")\n";
}

// The certificate as hapstate-inspect summary --json's "certificate" (docs/inspect.md).
Json certificate_json(const Certificate& c) {
  Json j;
  j["stale"] = c.stale;
  j["complete"] = c.complete;
  j["playback_hash"] = c.playback_hash.hex();
  j["paths"] = c.paths;
  j["steps_per_path"] = c.steps_per_path;
  j["steps"] = c.steps;
  j["failed_steps"] = c.failed_steps;
  if (c.contact)
    j["contact"] = {{"steps", c.contact_steps}, {"onsets", c.onsets}, {"leavings", c.leavings}};
  else
    j["contact"] = nullptr;
  for (int s = 0; s < kNumSchemes; ++s) {
    const SchemeCertificate& sc = c.schemes[s];
    j["force_error"][scheme_name(s)] = {{"worst", sc.worst},
                                        {"p99", sc.p99},
                                        {"worst_newtons", sc.worst_n},
                                        {"p99_newtons", sc.p99_n}};
    j["deformation_error"][scheme_name(s)] = {{"worst", sc.deformation_worst},
                                              {"p99", sc.deformation_p99}};
  }
  if (c.complete) {
    Json devices = Json::array();
    for (const DeviceLimit& d : kDeviceLimits)
      devices.push_back({{"device", d.name},
                         {"n_per_mm", d.n_per_mm},
                         {"within", c.stiffness_n_per_mm <= d.n_per_mm}});
    j["stiffness"] = {{"largest_n_per_mm", c.stiffness_n_per_mm}, {"devices", devices}};
    j["haptic_query_ns"] = {
        {"median", c.query_median_ns}, {"p99_9", c.query_p999_ns}, {"queries", c.queries}};
  } else {
    j["stiffness"] = nullptr;
    j["haptic_query_ns"] = nullptr;
  }
  Json worst = Json::array();
  for (const CertificateLocation& l : c.worst)
    worst.push_back({{"scheme", scheme_name(l.scheme)},
                     {"seed", l.seed},
                     {"step", l.step},
                     {"probe", l.probe},
                     {"cell", l.cell},
                     {"checkpoint", l.checkpoint},
                     {"force_error", l.error},
                     {"force_error_newtons", l.error_n}});
  j["worst"] = worst;
  Json sided = Json::array();
  for (const CertificateEquilibria& e : c.equilibria) {
    Json row = {{"seed", e.seed},
                {"step", e.step},
                {"axis", std::string(1, "xyz"[e.axis])},
                {"along", e.along},
                {"verdict", equilibria_name(e.verdict)}};
    row["force_minus"] = e.force_minus ? Json(*e.force_minus) : Json(nullptr);
    row["force_plus"] = e.force_plus ? Json(*e.force_plus) : Json(nullptr);
    const double d = difference(e);
    row["difference_newtons"] = std::isnan(d) ? Json(nullptr) : Json(d);
    sided.push_back(row);
  }
  j["equilibria"] = sided;
  return j;
}

}  // namespace

ContentHash certified_hash(std::uint64_t playback_source_hash) {
  ContentHasher h;
  h.update(static_cast<std::int64_t>(playback_source_hash));
  h.update(static_cast<std::int64_t>(playback_code_id()));
  return h.value();
}

Certificate summarise_certificate(const std::vector<CertificatePath>& paths,
                                  const std::vector<CertificateEquilibria>& equilibria,
                                  const std::optional<CertificateRun>& run,
                                  const std::optional<ContentHash>& current, bool contact,
                                  int worst_per_scheme) {
  Certificate c;
  if (paths.empty()) return c;
  c.present = true;
  c.contact = contact;
  c.playback_hash = paths.front().playback_hash;
  c.stale = !current || *current != c.playback_hash;
  for (const CertificatePath& p : paths) c.stale = c.stale || p.playback_hash != c.playback_hash;
  c.paths = static_cast<int>(paths.size());
  c.steps_per_path = paths.front().steps;
  std::array<std::vector<double>, 2> rel, newtons, deform;
  std::vector<CertificateLocation> all;
  for (const CertificatePath& p : paths) {
    bool touching = false;
    for (const CertificateStep& r : p.rows) {
      ++c.steps;
      if (!r.solved) {
        ++c.failed_steps;
        continue;
      }
      const bool now = r.force > 0;
      c.contact_steps += now;
      c.onsets += now && !touching;
      c.leavings += !now && touching;
      touching = now;
      for (int s = 0; s < kNumSchemes; ++s) {
        const double e = p.max_force > 0 ? r.error[s] / p.max_force : 0.0;
        rel[s].push_back(e);
        newtons[s].push_back(r.error[s]);
        if (!r.onset) deform[s].push_back(r.deformation[s]);
        all.push_back({s, p.seed, r.step, r.probe, r.cell, r.checkpoint, e, r.error[s]});
      }
    }
  }
  for (int s = 0; s < kNumSchemes; ++s) {
    SchemeCertificate& sc = c.schemes[s];
    std::tie(sc.worst, sc.p99) = worst_p99(rel[s]);
    std::tie(sc.worst_n, sc.p99_n) = worst_p99(newtons[s]);
    std::tie(sc.deformation_worst, sc.deformation_p99) = worst_p99(deform[s]);
  }
  std::stable_sort(all.begin(), all.end(), [](const auto& a, const auto& b) {
    return a.scheme != b.scheme ? a.scheme > b.scheme : a.error > b.error;  // Hermite first
  });
  std::array<int, 2> taken{};
  for (const CertificateLocation& l : all)
    if (taken[l.scheme]++ < worst_per_scheme) c.worst.push_back(l);
  for (const CertificateEquilibria& e : equilibria)
    if (e.playback_hash == c.playback_hash) c.equilibria.push_back(e);
  if (run && run->playback_hash == c.playback_hash) {
    c.complete = true;
    c.stiffness_n_per_mm = run->stiffness / 1000.0;
    c.queries = run->queries;
    c.query_median_ns = run->query_median_ns;
    c.query_p999_ns = run->query_p999_ns;
  }
  return c;
}

CertificateText certificate_text(const Certificate& c) {
  if (!c.present) {
    const char* none = "certificate: none (hapstate-certify has not run: docs/certificate.md)\n";
    return {"null", none, none};
  }
  const Json j = certificate_json(c);

  std::ostringstream t;
  t << "certificate (hapstate-certify: the paper's experiment on "
    << plural(c.paths, "random path", "random paths") << " of " << c.steps_per_path << " steps, "
    << plural(c.failed_steps, "failed precise solve", "failed precise solves") << " left out)";
  if (c.stale)
    t << ": STALE, measured on another playback file or by another version of the playback code; "
         "run hapstate-certify again";
  else if (!c.complete)
    t << ": incomplete (interrupted); run hapstate-certify again to finish it";
  t << "\n";
  char line[400];
  for (int s = 1; s >= 0; --s) {
    const SchemeCertificate& sc = c.schemes[s];
    std::snprintf(line, sizeof line,
                  "  %-9s force error worst %s (%s N), 99th percentile %s (%s N); deformation "
                  "worst %s, 99th percentile %s\n",
                  kSchemeTitles[s], percent(sc.worst).c_str(), sci(sc.worst_n).c_str(),
                  percent(sc.p99).c_str(), sci(sc.p99_n).c_str(),
                  percent(sc.deformation_worst).c_str(), percent(sc.deformation_p99).c_str());
    t << line;
  }
  t << "  (a force error is |f - f*| over the path's largest |f*|, as hapstate-eval's)\n";
  bool outside = false;
  for (const SchemeCertificate& sc : c.schemes)
    outside = outside || !(sc.worst <= kPaperForceBound) ||
              !(sc.deformation_worst <= kPaperDeformationBound);
  if (outside) {
    std::snprintf(line, sizeof line,
                  "  outside the paper's bounds (force %.0f %%, deformation %.0f %%): the worst "
                  "places are below; what to change, in the order of cost: docs/certificate.md, "
                  "\"When it is not good enough\"\n",
                  100 * kPaperForceBound, 100 * kPaperDeformationBound);
    t << line;
  }
  if (c.contact)
    t << "  contact: " << c.contact_steps << " of " << c.steps - c.failed_steps
      << " steps touching, " << plural(c.onsets, "onset", "onsets") << ", "
      << plural(c.leavings, "leaving", "leavings") << "\n";
  if (c.complete) {
    std::snprintf(line, sizeof line, "  largest stored stiffness %.3g N/mm:", c.stiffness_n_per_mm);
    t << line;
    const char* sep = " ";
    for (const DeviceLimit& d : kDeviceLimits) {
      std::snprintf(line, sizeof line, "%s%s %s (%.3g N/mm)", sep, d.name,
                    c.stiffness_n_per_mm <= d.n_per_mm ? "can render it" : "cannot render it",
                    d.n_per_mm);
      t << line;
      sep = "; ";
    }
    std::snprintf(line, sizeof line,
                  "\n  haptic query (Hermite force()): median %.0f ns, 99.9th percentile %.0f ns "
                  "over %lld queries along the paths\n",
                  c.query_median_ns, c.query_p999_ns, static_cast<long long>(c.queries));
    t << line;
  }
  int shown = 0;
  for (const CertificateLocation& l : c.worst) {
    if (l.scheme != 1 || shown >= 3) continue;
    ++shown;
    std::snprintf(line, sizeof line,
                  "  worst Hermite: %s (%s N) at seed %d step %d, probe (%.4g, %.4g, %.4g), cell "
                  "(%d, %d, %d), nearest check-point (%d, %d, %d)\n",
                  percent(l.error).c_str(), sci(l.error_n).c_str(), l.seed, l.step, l.probe[0],
                  l.probe[1], l.probe[2], l.cell[0], l.cell[1], l.cell[2], l.checkpoint[0],
                  l.checkpoint[1], l.checkpoint[2]);
    t << line;
  }
  for (std::size_t i = 0; i < c.equilibria.size();) {
    std::size_t end = i;
    while (end < c.equilibria.size() && c.equilibria[end].seed == c.equilibria[i].seed &&
           c.equilibria[end].step == c.equilibria[i].step)
      ++end;
    std::string whose;
    for (int s = 1; s >= 0; --s)
      for (const CertificateLocation& l : c.worst)
        if (l.scheme == s && l.error == c.schemes[s].worst && l.seed == c.equilibria[i].seed &&
            l.step == c.equilibria[i].step) {
          whose += std::string(whose.empty() ? ", the worst of " : " and ") + kSchemeTitles[s];
          break;
        }
    equilibria_lines(t,
                     {c.equilibria.begin() + static_cast<std::ptrdiff_t>(i),
                      c.equilibria.begin() + static_cast<std::ptrdiff_t>(end)},
                     whose);
    i = end;
  }
  bool jumps = false;
  for (const CertificateEquilibria& e : c.equilibria)
    jumps = jumps || e.verdict == Equilibria::kTwo || e.verdict == Equilibria::kEnds;
  std::snprintf(line, sizeof line,
                "certificate%s: worst force error Hermite %s, trilinear %s of the path's largest "
                "force over %s%s (hapstate-inspect summary has the rest)\n",
                c.stale ? " (STALE)" : "", percent(c.schemes[1].worst).c_str(),
                percent(c.schemes[0].worst).c_str(),
                plural(c.paths, "random path", "random paths").c_str(),
                jumps ? "; the force jumps at a worst step" : "");
  return {j.dump(), t.str(), line};
}

}  // namespace hapstate
