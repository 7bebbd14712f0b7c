#include "io/probe_path.h"

#include "util/error.h"
#include "util/text.h"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <string>

namespace hapstate {
namespace {

std::vector<std::string> split_commas(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string cell;
  while (std::getline(ss, cell, ',')) out.push_back(trim(cell));
  return out;
}

}  // namespace

ProbePath read_probe_path(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw InputError(file.string() + ": cannot open probe path");
  ProbePath path;
  std::string line;
  int line_no = 0;
  bool header_seen = false;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#') continue;
    const auto cells = split_commas(t);
    const std::string where = file.string() + ":" + std::to_string(line_no) + ": ";
    if (!header_seen) {
      if (cells.size() < 3 || cells[0] != "x" || cells[1] != "y" || cells[2] != "z")
        throw InputError(where + "expected the header 'x,y,z', found '" + t + "'");
      header_seen = true;
      continue;
    }
    if (cells.size() < 3) throw InputError(where + "expected 3 numbers x,y,z, found '" + t + "'");
    Eigen::Vector3d p;
    for (int c = 0; c < 3; ++c) {
      std::size_t used = 0;
      try {
        p[c] = std::stod(cells[c], &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used == 0 || used != cells[c].size() || !std::isfinite(p[c]))
        throw InputError(where + "column " + "xyz"[c] + ": '" + cells[c] +
                         "' is not a finite number");
    }
    path.push_back(p);
  }
  if (!header_seen)
    throw InputError(file.string() + ": empty probe path (expected header 'x,y,z')");
  if (path.empty()) throw InputError(file.string() + ": probe path has no points");
  return path;
}

void write_probe_path(const ProbePath& path, const std::filesystem::path& file) {
  std::ofstream out(file);
  if (!out) throw InputError(file.string() + ": cannot write probe path");
  out << "x,y,z\n" << std::setprecision(17);
  for (const auto& p : path) out << p.x() << ',' << p.y() << ',' << p.z() << '\n';
}

ProbePath straight_path(const Eigen::Vector3d& from, const Eigen::Vector3d& to, int steps) {
  ProbePath path;
  for (int k = 1; k <= steps; ++k) path.push_back(from + (to - from) * (double(k) / steps));
  return path;
}

std::uint64_t RandomDirections::next() {
  std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

double RandomDirections::uniform() { return (next() >> 11) * (1.0 / 9007199254740992.0); }

Eigen::Vector3d RandomDirections::direction() {
  const double z = 2.0 * uniform() - 1.0;
  const double phi = 2.0 * M_PI * uniform();
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

ProbePath random_path(const Eigen::Vector3d& start, int steps, double step_length,
                      const Eigen::Vector3d& box_min, const Eigen::Vector3d& box_max,
                      std::uint64_t seed) {
  RandomDirections rng(seed);
  ProbePath path;
  Eigen::Vector3d p = start;
  for (int k = 0; k < steps; ++k) {
    Eigen::Vector3d q = p + step_length * rng.direction();
    for (int c = 0; c < 3; ++c) {
      if (q[c] > box_max[c]) q[c] = 2 * box_max[c] - q[c];
      if (q[c] < box_min[c]) q[c] = 2 * box_min[c] - q[c];
      q[c] = std::min(box_max[c], std::max(box_min[c], q[c]));
    }
    path.push_back(q);
    p = q;
  }
  return path;
}

}  // namespace hapstate
