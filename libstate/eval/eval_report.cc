#include "eval/eval_report.h"

#include "util/error.h"
#include "util/paper_bounds.h"
#include "util/text.h"

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace hapstate {
namespace {

// The plot script, run by python3 from standard input: argv = csv png title.
constexpr const char* kPlotScript = R"PY(
import csv, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import matplotlib.ticker
rows = list(csv.DictReader(open(sys.argv[1])))
steps = [int(r["step"]) for r in rows]
schemes = [c[:-len("_force_error")] for c in rows[0] if c.endswith("_force_error")]
fig, ax = plt.subplots(figsize=(7, 4))
colours = {("trilinear", "force"): "C0", ("hermite", "force"): "C1",
           ("trilinear", "deformation"): "C3", ("hermite", "deformation"): "C2"}
curves = []  # (label, values in %, style, colour)
for s in schemes:
    ls = "-" if s == "trilinear" else "--"
    curves.append((s + ": force", [100 * float(r[s + "_force_error"]) for r in rows], "o" + ls,
                   colours.get((s, "force"), None)))
    col = s + "_deformation_error_all"
    if float(rows[0][col]) < 0:
        col = s + "_deformation_error_surface"
    curves.append((s + ": deformation" + (" (surface)" if col.endswith("surface") else ""),
                   [100 * float(r[col]) for r in rows], "s" + ls, colours.get((s, "deformation"), None)))
# A curve equal to an earlier one hides it: say so in the legend.
for i, (label, values, style, colour) in enumerate(curves):
    for earlier in curves[:i]:
        if earlier[1] == values:
            label += " (same as " + earlier[0] + ", drawn over it)"
            break
    curves[i] = (label, values, style, colour)
# A logarithmic axis: the Hermite errors (often 1e-5 %) and a contact spike of several per cent
# are read on the same figure without clipping. An error of exactly zero (or below 1e-7 of the
# largest) has no place on it: it is drawn on the axis's floor with an open marker and said in
# the legend.
positive = [v for _, values, _, _ in curves for v in values if v > 0]
top = max(positive) if positive else 1.0
floor = max(min(positive) if positive else 1e-6, top * 1e-7) / 2
for label, values, style, colour in curves:
    under = sum(1 for v in values if v <= floor)
    if under:
        label += " (%d step%s 0 or below %.2g %%: open, on the floor)" % (
            under, "" if under == 1 else "s", floor)
    line, = ax.plot(steps, [max(v, floor) for v in values], style, color=colour, label=label,
                    markersize=4)
    if under:
        ax.plot([x for x, v in zip(steps, values) if v <= floor], [floor] * under, "o",
                markerfacecolor="white", markeredgecolor=line.get_color(), markersize=5)
ax.axhline(4.0, color="grey", linewidth=0.8, linestyle=":")
ax.annotate("the paper's 4 % (force)", (0.01, 4.0), xycoords=("axes fraction", "data"),
            textcoords="offset points", xytext=(2, 3), fontsize=7, color="grey")
ax.set_yscale("log")
ax.set_ylim(bottom=floor / 1.5, top=max(top, 4.0) * 3)
ax.yaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: "%g %%" % v))
ax.set_xlabel("step of the probe path")
ax.set_ylabel("relative error (log scale)")
ax.set_xlim(min(steps) - 0.5, max(steps) + 0.5)
ax.xaxis.set_major_locator(matplotlib.ticker.MaxNLocator(integer=True))
ax.grid(True, which="major", alpha=0.3)
ax.legend(fontsize=7, loc="best")
ax.set_title(sys.argv[3], fontsize=9)
fig.tight_layout()
fig.savefig(sys.argv[2], dpi=120)
)PY";

std::string shell_quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// The p-quantile (0..1) of `v` by the nearest rank; v is sorted in place.
double quantile(std::vector<double>* v, double p) {
  std::sort(v->begin(), v->end());
  if (v->empty()) return 0;
  const auto k = static_cast<std::size_t>(std::ceil(p * static_cast<double>(v->size())));
  return (*v)[std::min(v->size() - 1, k > 0 ? k - 1 : 0)];
}

}  // namespace

SchemeSummary summarize(const EvalResult& result, std::size_t scheme) {
  SchemeSummary e;
  int solved = 0, counted = 0;
  double fsum = 0, asum = 0, ssum = 0;
  for (const EvalStep& st : result.steps) {
    if (!st.solved) continue;
    ++solved;
    const SchemeResult& r = st.schemes[scheme];
    e.force_max = std::max(e.force_max, r.force_error), fsum += r.force_error;
    if (st.contact_onset) {
      e.onset_deformation_max =
          std::max({e.onset_deformation_max, r.deformation_error_all, r.deformation_error_surface});
      continue;
    }
    ++counted;
    e.deformation_all_max = std::max(e.deformation_all_max, r.deformation_error_all);
    asum += r.deformation_error_all;
    e.deformation_surface_max = std::max(e.deformation_surface_max, r.deformation_error_surface);
    ssum += r.deformation_error_surface;
  }
  e.force_mean = fsum / std::max(solved, 1);
  e.deformation_all_mean = asum / std::max(counted, 1);
  e.deformation_surface_mean = ssum / std::max(counted, 1);
  return e;
}

std::string seeds_table(const std::vector<EvalResult>& runs, std::uint64_t first_seed) {
  std::ostringstream t;
  char line[320];
  if (runs.empty()) return "";
  std::snprintf(line, sizeof line,
                "%zu random paths (seeds %llu-%llu), %s; per path the largest error over its "
                "steps, as in the single-path table\n",
                runs.size(), static_cast<unsigned long long>(first_seed),
                static_cast<unsigned long long>(first_seed + runs.size() - 1),
                runs.front()
                    .path_description.substr(0, runs.front().path_description.find(", seed"))
                    .c_str());
  t << line;
  t << "scheme      force error (max over a path)                deformation error (max over a "
       "path)\n"
       "               median        90 %   largest (seed)          median        90 %   largest "
       "(seed)\n";
  for (std::size_t s = 0; s < runs.front().schemes.size(); ++s) {
    std::vector<double> force, deformation;
    std::size_t worst_force = 0, worst_deformation = 0;
    int over_paper = 0;
    for (std::size_t k = 0; k < runs.size(); ++k) {
      const SchemeSummary e = summarize(runs[k], s);
      force.push_back(e.force_max);
      deformation.push_back(e.deformation_max(runs[k]));
      if (force.back() > force[worst_force]) worst_force = k;
      if (deformation.back() > deformation[worst_deformation]) worst_deformation = k;
      over_paper += e.force_max > kPaperForceBound || deformation.back() > kPaperDeformationBound;
    }
    const double fw = force[worst_force], dw = deformation[worst_deformation];
    const double f50 = quantile(&force, 0.5), f90 = quantile(&force, 0.9);
    const double d50 = quantile(&deformation, 0.5), d90 = quantile(&deformation, 0.9);
    std::snprintf(line, sizeof line, "%-10s %11s %11s %10s (%llu)    %11s %11s %10s (%llu)\n",
                  scheme_name(runs.front().schemes[s]), percent(f50).c_str(), percent(f90).c_str(),
                  percent(fw).c_str(), static_cast<unsigned long long>(first_seed) + worst_force,
                  percent(d50).c_str(), percent(d90).c_str(), percent(dw).c_str(),
                  static_cast<unsigned long long>(first_seed) + worst_deformation);
    t << line;
    std::snprintf(line, sizeof line,
                  "  %s: %d of %zu paths outside the paper's bounds (force 4 %%, deformation "
                  "14 %%)\n",
                  scheme_name(runs.front().schemes[s]), over_paper, runs.size());
    t << line;
  }
  int failed = 0;
  for (const EvalResult& r : runs) failed += failed_steps(r);
  if (failed > 0) {
    std::snprintf(line, sizeof line, "%d step(s) failed to solve precisely (left out)\n", failed);
    t << line;
  }
  return t.str();
}

void write_seeds_csv(const std::vector<EvalResult>& runs, std::uint64_t first_seed,
                     const std::filesystem::path& file) {
  std::ofstream out(file);
  if (!out) throw InputError(file.string() + ": cannot write");
  out.precision(12);
  out << "seed,max_exact_force";
  if (!runs.empty())
    for (Scheme s : runs.front().schemes)
      out << ',' << scheme_name(s) << "_force_error_max," << scheme_name(s)
          << "_deformation_error_max";
  out << '\n';
  for (std::size_t k = 0; k < runs.size(); ++k) {
    out << first_seed + k << ',' << runs[k].max_exact_force;
    for (std::size_t s = 0; s < runs[k].schemes.size(); ++s) {
      const SchemeSummary e = summarize(runs[k], s);
      out << ',' << e.force_max << ',' << e.deformation_max(runs[k]);
    }
    out << '\n';
  }
  if (!out.flush()) throw InputError(file.string() + ": write failed");
}

void write_eval_csv(const EvalResult& result, const std::filesystem::path& file) {
  std::ofstream out(file);
  if (!out) throw InputError(file.string() + ": cannot write");
  out.precision(12);
  out << "step,x,y,z,fx_exact,fy_exact,fz_exact,solved";
  for (Scheme s : result.schemes) {
    const std::string n = scheme_name(s);
    out << ',' << n << "_fx," << n << "_fy," << n << "_fz," << n << "_force_error," << n
        << "_deformation_error_all," << n << "_deformation_error_surface";
  }
  out << '\n';
  for (std::size_t k = 0; k < result.steps.size(); ++k) {
    const EvalStep& st = result.steps[k];
    out << k + 1 << ',' << st.probe.x() << ',' << st.probe.y() << ',' << st.probe.z() << ','
        << st.exact_force.x() << ',' << st.exact_force.y() << ',' << st.exact_force.z() << ','
        << (st.solved ? 1 : 0);
    for (const SchemeResult& r : st.schemes)
      out << ',' << r.force.x() << ',' << r.force.y() << ',' << r.force.z() << ',' << r.force_error
          << ',' << r.deformation_error_all << ',' << r.deformation_error_surface;
    out << '\n';
  }
  if (!out.flush()) throw InputError(file.string() + ": write failed");
}

std::string eval_table(const EvalResult& result) {
  std::ostringstream t;
  char line[320];
  int solved = 0;
  double solve_ms = 0;
  for (const EvalStep& st : result.steps) {
    solved += st.solved;
    solve_ms += st.solve_ms;
  }
  std::snprintf(
      line, sizeof line,
      "%zu steps (%d solved precisely), grid spacing (%.4g, %.4g, %.4g), max |f*| = %.4g N\n",
      result.steps.size(), solved, result.spacing.x(), result.spacing.y(), result.spacing.z(),
      result.max_exact_force);
  t << line;
  t << result.path_description << "\n";
  if (result.outside_grid > 0) {
    std::snprintf(line, sizeof line,
                  "%d step(s) lie outside the precomputed grid: playback extends the boundary "
                  "values there, so large errors are expected\n",
                  result.outside_grid);
    t << line;
  }
  t << "force error |f - f*| / max|f*| over the path; deformation error ||u - u*|| / ||u*|| per "
       "step (f*, u*: the precise solve; each scheme interpolates the displacements as it does the "
       "force: trilinear, or cubic Hermite from the stored displacement slopes)\n";
  t << "scheme      force error               deformation error (all)   deformation error "
       "(surface)\n"
       "                    max        mean            max        mean            max        "
       "mean\n";
  std::string verdicts;
  int onset = 0;  // solved steps left out of the deformation columns
  for (const EvalStep& st : result.steps) onset += st.solved && st.contact_onset;
  double onset_max = 0;
  for (std::size_t s = 0; s < result.schemes.size(); ++s) {
    const SchemeSummary e = summarize(result, s);
    onset_max = std::max(onset_max, e.onset_deformation_max);
    char all[64];
    if (result.has_all_nodes)
      std::snprintf(all, sizeof all, "%11s %11s", percent(e.deformation_all_max).c_str(),
                    percent(e.deformation_all_mean).c_str());
    else
      std::snprintf(all, sizeof all, "%-23s", "(surface only)");
    std::snprintf(line, sizeof line, "%-10s %11s %11s    %s    %11s %11s\n",
                  scheme_name(result.schemes[s]), percent(e.force_max).c_str(),
                  percent(e.force_mean).c_str(), all, percent(e.deformation_surface_max).c_str(),
                  percent(e.deformation_surface_mean).c_str());
    t << line;
    const double deformation = e.deformation_max(result);
    const bool good = e.force_max <= kPaperForceBound && deformation <= kPaperDeformationBound;
    std::snprintf(line, sizeof line,
                  "  %s: max force error %s %s 4 %%, max deformation error "
                  "%s %s 14 %%: %s\n",
                  scheme_name(result.schemes[s]), percent(e.force_max).c_str(),
                  e.force_max <= kPaperForceBound ? "<=" : ">", percent(deformation).c_str(),
                  deformation <= kPaperDeformationBound ? "<=" : ">",
                  good ? "within the paper's bounds" : "outside the paper's bounds");
    verdicts += line;
  }
  if (onset > 0) {
    std::snprintf(line, sizeof line,
                  "(deformation columns leave out %d step(s) within one grid spacing of a first "
                  "contact, where u* is small and the relative error large: up to %.1f %%)\n",
                  onset, 100 * onset_max);
    t << line;
  }
  t << "verdict against the paper's Matlab prototype (Peterlik & Matyska 2007: force <= 4 %, "
       "deformation <= 14 %):\n"
    << verdicts;
  if (!result.has_all_nodes)
    t << "(the playback file holds the surface nodes only: index with --nodes all for the all-node "
         "error)\n";
  std::snprintf(line, sizeof line, "precise Newton solve: %.2f ms per step (mean)\n",
                solve_ms / std::max<std::size_t>(result.steps.size(), 1));
  t << line;
  for (std::size_t k = 0; k < result.steps.size(); ++k)
    if (!result.steps[k].solved)
      t << "step " << k + 1 << ": precise solve failed: " << result.steps[k].failure << '\n';
  return t.str();
}

void plot_eval(const std::filesystem::path& csv, const std::filesystem::path& png,
               const std::string& title) {
  // Debian's interpreter first: it is the one python3-matplotlib installs into.
  const std::string python =
      std::filesystem::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  const std::string command = python + " - " + shell_quote(csv.string()) + " " +
                              shell_quote(png.string()) + " " + shell_quote(title) + " 2>&1";
  FILE* pipe = ::popen(command.c_str(), "w");
  if (!pipe) throw InputError(png.string() + ": cannot start " + python + " to plot");
  std::fputs(kPlotScript, pipe);
  const int status = ::pclose(pipe);
  if (status != 0 || !std::filesystem::exists(png))
    throw InputError(png.string() + ": plotting with " + python +
                     " and matplotlib failed (install python3-matplotlib); the CSV " +
                     csv.string() + " holds the numbers");
}

}  // namespace hapstate
