#include "eval/stress_report.h"

#include "util/error.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>

namespace hapstate {
namespace {

std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

// CSV field: quoted, inner quotes doubled.
std::string quoted(const std::string& s) {
  std::string out(1, '"');
  for (char ch : s) {
    if (ch == '"') out.push_back('"');
    out.push_back(ch);
  }
  out.push_back('"');
  return out;
}

struct Tally {
  int cases = 0, converged = 0;
  std::string rate() const {
    return std::to_string(converged) + "/" + std::to_string(cases) +
           (cases ? " (" + fmt("%.0f", 100.0 * converged / cases) + " %)" : "");
  }
};

// Success rate per value of one axis, as a two-row Markdown table.
std::string axis_table(const std::vector<StressOutcome>& outcomes, const std::string& title,
                       const std::function<std::string(const StressCase&)>& key) {
  std::vector<std::string> order;
  std::map<std::string, Tally> tally;
  for (const StressOutcome& o : outcomes) {
    const std::string k = key(o.c);
    if (!tally.count(k)) order.push_back(k);
    Tally& t = tally[k];
    ++t.cases;
    if (o.status == "converged") ++t.converged;
  }
  std::string head = "| " + title + " |", rule = "|---|", row = "| converged |";
  for (const std::string& k : order) {
    // append, not " " + k + " |": GCC 12 warns (-Wrestrict, a false positive) on the latter.
    head.append(" ").append(k).append(" |");
    rule += "---|";
    row.append(" ").append(tally[k].rate()).append(" |");
  }
  return head + "\n" + rule + "\n" + row + "\n\n";
}

// The converged share per law (rows) and Poisson's ratio (columns).
std::string law_nu_table(const std::vector<StressOutcome>& outcomes) {
  std::ostringstream s;
  std::vector<double> nus;
  std::vector<Law> laws;
  for (const StressOutcome& o : outcomes) {
    if (std::find(nus.begin(), nus.end(), o.c.poisson) == nus.end()) nus.push_back(o.c.poisson);
    if (std::find(laws.begin(), laws.end(), o.c.law) == laws.end()) laws.push_back(o.c.law);
  }
  s << "Converged per law and Poisson's ratio:\n\n| law \\ nu |";
  for (double nu : nus) s << " " << nu << " |";
  s << " all |\n|---|";
  for (std::size_t i = 0; i <= nus.size(); ++i) s << "---|";
  s << "\n";
  for (Law law : laws) {
    s << "| " << law_name(law) << " |";
    Tally all;
    for (double nu : nus) {
      Tally t;
      for (const StressOutcome& o : outcomes)
        if (o.c.law == law && o.c.poisson == nu) {
          ++t.cases;
          t.converged += o.status == "converged";
        }
      all.cases += t.cases;
      all.converged += t.converged;
      s << " " << t.rate() << " |";
    }
    s << " " << all.rate() << " |\n";
  }
  s << "\n";
  return s.str();
}

// The strain the converged cases reached per law, probe and load, and the meshes' quality.
std::string strain_table(const std::vector<StressOutcome>& outcomes) {
  std::ostringstream s;
  s << "Strain reached by the converged cases (largest and smallest principal stretch of any tet "
       "at the end of the path, over the cases of the row; smallest det F; linear and stvk allow "
       "det F <= 0):\n\n| law / probe / load | max stretch | min stretch | min det F "
       "|\n|---|---|---|---|\n";
  std::map<std::string, StretchRange> reach;
  std::vector<std::string> order;
  for (const StressOutcome& o : outcomes) {
    if (o.status != "converged") continue;
    const std::string k = std::string(law_name(o.c.law)) + " / " + stress_name(o.c.probe) + " / " +
                          stress_name(o.c.load);
    if (!reach.count(k)) {
      order.push_back(k);
      reach[k] = StretchRange{0, 1e300, 1e300};  // max of the max, min of the min
    }
    StretchRange& r = reach[k];
    r.max_stretch = std::max(r.max_stretch, o.strain.max_stretch);
    r.min_stretch = std::min(r.min_stretch, o.strain.min_stretch);
    r.min_jacobian = std::min(r.min_jacobian, o.strain.min_jacobian);
  }
  for (const std::string& k : order)
    s << "| " << k << " | " << fmt("%.2f", reach[k].max_stretch) << " | "
      << fmt("%.2f", reach[k].min_stretch) << " | " << fmt("%.2f", reach[k].min_jacobian) << " |\n";
  std::map<std::string, double> quality;
  for (const StressOutcome& o : outcomes) quality[stress_name(o.c.mesh)] = o.mesh_min_quality;
  s << "\nMesh min quality q = 3 r_in / r_circ:";
  for (const auto& [name, q] : quality) s << " " << name << " " << fmt("%.3f", q) << ";";
  s << "\n\n";

  return s.str();
}

}  // namespace

void write_stress_csv(const std::vector<StressOutcome>& outcomes,
                      const std::filesystem::path& file) {
  std::ofstream out(file);
  if (!out) throw EnvironmentError("cannot write " + file.string());
  out << "law,nu,load,step,mesh,probe,status,failure,reason,moves,moves_done,reached,iterations,"
         "substeps,cutbacks,factorisations,psd_fallbacks,split_moves,wall_ms,max_force_N,max_"
         "stretch,"
         "min_stretch,min_jacobian,mesh_min_quality,retry_fine_step\n";
  for (const StressOutcome& o : outcomes) {
    out << law_name(o.c.law) << "," << o.c.poisson << "," << stress_name(o.c.load) << ","
        << stress_name(o.c.step) << "," << stress_name(o.c.mesh) << "," << stress_name(o.c.probe)
        << "," << o.status << "," << o.failure << "," << quoted(o.reason) << "," << o.moves << ","
        << o.moves_done << "," << fmt("%.4f", o.reached) << "," << o.iterations << "," << o.substeps
        << "," << o.cutbacks << "," << o.factorisations << "," << o.psd_fallbacks << ","
        << o.split_moves << "," << fmt("%.1f", o.wall_ms) << "," << fmt("%.6g", o.max_force) << ","
        << fmt("%.4f", o.strain.max_stretch) << "," << fmt("%.4f", o.strain.min_stretch) << ","
        << fmt("%.4f", o.strain.min_jacobian) << "," << fmt("%.4f", o.mesh_min_quality) << ","
        << o.retry << "\n";
  }
  if (!out) throw EnvironmentError("cannot write " + file.string());
}

std::string stress_markdown(const std::vector<StressOutcome>& outcomes) {
  std::ostringstream s;
  int converged = 0, bugs = 0, capped = 0;
  double wall = 0;
  for (const StressOutcome& o : outcomes) {
    converged += o.status == "converged";
    bugs += o.bug();
    capped += o.status == "wall_cap";
    wall += o.wall_ms;
  }
  s << "Cases: " << outcomes.size() << ", converged " << converged << ", failed with a reason "
    << outcomes.size() - converged - bugs - capped << ", wall-time cap " << capped
    << ", bugs (NaN in a converged output, exception, failure without a reason) " << bugs
    << "; solver time " << fmt("%.1f", wall / 1e3) << " s.\n\n";

  s << law_nu_table(outcomes);
  s << axis_table(outcomes, "load",
                  [](const StressCase& c) { return std::string(stress_name(c.load)); });
  s << axis_table(outcomes, "step",
                  [](const StressCase& c) { return std::string(stress_name(c.step)); });
  s << axis_table(outcomes, "mesh",
                  [](const StressCase& c) { return std::string(stress_name(c.mesh)); });
  s << axis_table(outcomes, "probe",
                  [](const StressCase& c) { return std::string(stress_name(c.probe)); });

  s << strain_table(outcomes);

  // Moves rescued by the split fallback.
  int rescued = 0;
  std::string rescued_ids;
  for (const StressOutcome& o : outcomes)
    if (o.split_moves > 0) {
      ++rescued;
      rescued_ids +=
          (rescued_ids.empty() ? "" : ", ") + o.c.id() + " (" + std::to_string(o.split_moves) + ")";
    }
  s << "Cases in which a failed move converged split into 4 or 16 moves (the solver's fallback; "
       "moves so rescued in brackets): "
    << rescued << (rescued ? ": " + rescued_ids : std::string()) << ".\n\n";

  // Failures.
  s << "Failures (retry: the same case with moves of a quarter grid spacing):\n\n"
       "| case | status | failure | reached | strain at last converged state (max / min stretch) | "
       "reason | retry |\n"
       "|---|---|---|---|---|---|---|\n";
  for (const StressOutcome& o : outcomes) {
    if (o.status == "converged") continue;
    s << "| " << o.c.id() << " | " << o.status << " | " << o.failure << " | "
      << fmt("%.0f %%", 100 * o.reached) << " | " << fmt("%.2f", o.strain.max_stretch) << " / "
      << fmt("%.2f", o.strain.min_stretch) << " | " << o.reason << " | "
      << (o.retry.empty() ? "-" : o.retry) << " |\n";
  }
  return s.str();
}

}  // namespace hapstate
