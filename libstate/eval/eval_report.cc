#include "eval/eval_report.h"

#include "util/error.h"

#include <sys/wait.h>

#include <algorithm>
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
# One spike (the first contact of a probe) must not flatten the rest: values above 5x the 90th
# percentile are spikes; the axis ends just above the rest and the spikes' values are written.
every = sorted(v for _, values, _, _ in curves for v in values)
p90 = every[int(0.9 * (len(every) - 1))] if every else 0.0
rest = [v for v in every if v <= 5 * p90]
clip = 1.1 * rest[-1] if p90 > 0 and rest and rest[-1] < every[-1] else None
for label, values, style, colour in curves:
    ax.plot(steps, [min(v, clip) if clip else v for v in values], style, color=colour, label=label,
            markersize=4)
    if clip:
        for x, v in zip(steps, values):
            if v > clip:
                ax.annotate("%.3g %%" % v, (x, clip), textcoords="offset points", xytext=(0, -10),
                            ha="center", fontsize=7, color=colour)
ax.set_xlabel("step of the probe path")
ax.set_ylabel("relative error (%)")
ax.set_xlim(min(steps) - 0.5, max(steps) + 0.5)
ax.xaxis.set_major_locator(matplotlib.ticker.MaxNLocator(integer=True))
ax.set_ylim(bottom=0, top=clip * 1.05 if clip else None)
ax.grid(True, alpha=0.3)
ax.legend(fontsize=7)
ax.set_title(sys.argv[3] + ("\n(axis clipped at %.3g %%: larger values written at the top)" % clip
                           if clip else ""), fontsize=9)
fig.tight_layout()
fig.savefig(sys.argv[2], dpi=120)
)PY";

std::string shell_quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

}  // namespace

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
  t << "scheme      force error          deformation error (all)   deformation error (surface)\n"
       "            max      mean        max      mean             max      mean\n";
  constexpr double kPaperForce = 0.04, kPaperDeformation = 0.14;
  std::string verdicts;
  int onset = 0;  // solved steps left out of the deformation columns
  for (const EvalStep& st : result.steps) onset += st.solved && st.contact_onset;
  double onset_max = 0;
  for (std::size_t s = 0; s < result.schemes.size(); ++s) {
    double fmax = 0, fsum = 0, amax = 0, asum = 0, smax = 0, ssum = 0;
    int counted = 0;
    for (const EvalStep& st : result.steps) {
      if (!st.solved) continue;
      const SchemeResult& r = st.schemes[s];
      fmax = std::max(fmax, r.force_error), fsum += r.force_error;
      if (st.contact_onset) {
        onset_max = std::max({onset_max, r.deformation_error_all, r.deformation_error_surface});
        continue;
      }
      ++counted;
      amax = std::max(amax, r.deformation_error_all), asum += r.deformation_error_all;
      smax = std::max(smax, r.deformation_error_surface), ssum += r.deformation_error_surface;
    }
    const double n = std::max(solved, 1), m = std::max(counted, 1);
    char all[64];
    if (result.has_all_nodes)
      std::snprintf(all, sizeof all, "%6.2f %%  %6.2f %%", 100 * amax, 100 * asum / m);
    else
      std::snprintf(all, sizeof all, "%-17s", "(surface only)");
    std::snprintf(line, sizeof line, "%-10s %6.2f %%  %6.2f %%     %s         %6.2f %%  %6.2f %%\n",
                  scheme_name(result.schemes[s]), 100 * fmax, 100 * fsum / n, all, 100 * smax,
                  100 * ssum / m);
    t << line;
    const double deformation = result.has_all_nodes ? amax : smax;
    const bool good = fmax <= kPaperForce && deformation <= kPaperDeformation;
    std::snprintf(line, sizeof line,
                  "  %s: max force error %.2f %% %s 4 %%, max deformation error "
                  "%.2f %% %s 14 %%: %s\n",
                  scheme_name(result.schemes[s]), 100 * fmax, fmax <= kPaperForce ? "<=" : ">",
                  100 * deformation, deformation <= kPaperDeformation ? "<=" : ">",
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
