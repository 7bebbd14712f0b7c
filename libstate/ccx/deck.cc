#include "ccx/deck.h"

#include "io/probe_path.h"
#include "util/error.h"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

namespace hapstate {
namespace {

constexpr std::array<char, 3> kAxisName{'X', 'Y', 'Z'};
constexpr int kIdsPerLine = 8;
constexpr long kPrintOnlyStepEnd = 1000000;  // *NODE PRINT FREQUENCY: only the end of a step

// ccx reads each data field into 20 characters and silently drops the rest, so a number is
// written as the shortest text that reads back exactly, or else rounded to fit in 20.
constexpr int kCcxFieldWidth = 20;

std::string num(double v) {
  std::array<char, 64> buf;
  auto r = std::to_chars(buf.data(), buf.data() + buf.size(), v);
  for (int digits = 15; r.ptr - buf.data() > kCcxFieldWidth && digits > 0; --digits) {
    r = std::to_chars(buf.data(), buf.data() + buf.size(), v, std::chars_format::general, digits);
  }
  return std::string(buf.data(), r.ptr);
}

std::string set_name(const char* base, int component) {
  return std::string(base) + "_" + kAxisName[component];
}

void write_node_set(std::ostream& out, const std::string& name, const std::vector<int>& nodes) {
  out << "*NSET, NSET=" << name << "\n";
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    out << nodes[i] + 1 << ((i + 1) % kIdsPerLine == 0 || i + 1 == nodes.size() ? "\n" : ", ");
  }
}

std::string deck_error(const std::filesystem::path& dir, const std::string& what) {
  return "CalculiX export to " + dir.string() + ": " + what;
}

// Node sets derived from the DOF roles: per component, the fixed nodes and the probe nodes.
struct DofSets {
  std::array<std::vector<int>, 3> fixed, probe;
};

DofSets dof_sets(const Problem& p, const std::filesystem::path& dir) {
  const int n = p.mesh.num_nodes();
  const auto& role = p.constraints.role;
  if (static_cast<int>(role.size()) != 3 * n) {
    throw InputError(deck_error(dir, "constraints have " + std::to_string(role.size()) +
                                         " DOF roles for " + std::to_string(n) + " nodes"));
  }
  std::vector<char> is_probe_node(n, 0);
  for (int node : p.constraints.probe_nodes) {
    if (node < 0 || node >= n) {
      throw InputError(deck_error(dir, "probe node " + std::to_string(node) + " out of range"));
    }
    is_probe_node[node] = 1;
  }
  DofSets sets;
  for (int node = 0; node < n; ++node) {
    for (int c = 0; c < 3; ++c) {
      const DofRole r = role[3 * node + c];
      if (r == DofRole::kFixed) sets.fixed[c].push_back(node);
      if (r == DofRole::kProbe) {
        if (!is_probe_node[node]) {
          throw InputError(deck_error(dir, "DOF " + std::to_string(3 * node + c) +
                                               " follows the probe but node " +
                                               std::to_string(node) + " is not a probe node"));
        }
        sets.probe[c].push_back(node);
      }
    }
  }
  return sets;
}

void check_mesh(const Mesh& m, const std::filesystem::path& dir) {
  const int n = m.num_nodes();
  for (int e = 0; e < m.num_tets(); ++e) {
    for (int k = 0; k < 4; ++k) {
      if (m.tets(k, e) < 0 || m.tets(k, e) >= n) {
        throw InputError(deck_error(dir, "tet " + std::to_string(e) + " has node id " +
                                             std::to_string(m.tets(k, e)) + " out of range"));
      }
    }
    // ccx's C3D4 wants det[b-a, c-a, d-a] > 0, our convention too (ccx stops with
    // "nonpositive jacobian determinant" otherwise).
    Eigen::Matrix3d d;
    for (int k = 0; k < 3; ++k)
      d.col(k) = m.nodes.col(m.tets(k + 1, e)) - m.nodes.col(m.tets(0, e));
    if (!(d.determinant() > 0)) {
      throw InputError(deck_error(dir, "tet " + std::to_string(e) + " is not positively oriented"));
    }
  }
}

std::string step_cards(const CcxDeckOptions& o, bool nlgeom) {
  std::ostringstream s;
  const double inc = 1.0 / o.increments_per_step;
  if (!nlgeom) {
    s << "*STEP\n*STATIC\n";
    return s.str();
  }
  // INC: the most increments ccx may take in the step (matters only with cutbacks).
  s << "*STEP, NLGEOM, INC=" << std::max(100, 10 * o.increments_per_step) << "\n";
  if (o.allow_cutbacks) {
    s << "*STATIC\n" << num(inc) << ", 1.0, " << num(inc * 1e-4) << ", " << num(inc) << "\n";
  } else {
    s << "*STATIC, DIRECT\n" << num(inc) << ", 1.0\n";
  }
  // TIME INCREMENTATION: I_0, I_R, I_P, I_C, I_L, I_G, I_S, I_A. The divergence and
  // logarithmic checks are pushed back so that they do not fire while Newton converges
  // quadratically to the tight tolerances below.
  s << "*CONTROLS, PARAMETERS=TIME INCREMENTATION\n"
    << o.max_iterations / 2 << ", " << o.max_iterations / 2 << ", " << o.max_iterations << ", "
    << o.max_iterations << ", " << o.max_iterations << ", 4, , 5\n";
  // FIELD: R_n, C_n, q_0, q_u, R_p, epsilon, C_epsilon, R_l.
  s << "*CONTROLS, PARAMETERS=FIELD\n"
    << num(o.residual_tolerance) << ", " << num(o.correction_tolerance) << ", , , "
    << num(o.residual_tolerance) << ", 1e-5, " << num(o.correction_tolerance) << ", "
    << num(std::min(o.residual_tolerance, 1e-8)) << "\n";
  return s.str();
}

void write_meta(const Problem& p, int num_points, const std::filesystem::path& file) {
  const Eigen::Vector3d weight = probe_body_force(p);
  std::ofstream out(file);
  out << "{\n  \"format\": 1,\n  \"law\": \"" << law_name(p.material.law) << "\",\n"
      << "  \"first_point_time\": " << ccx_first_point_time(p) << ",\n"
      << "  \"probe_body_force\": [" << num(weight.x()) << ", " << num(weight.y()) << ", "
      << num(weight.z()) << "],\n"
      << "  \"unit\": " << num(p.unit) << ",\n  \"num_nodes\": " << p.mesh.num_nodes() << ",\n"
      << "  \"num_points\": " << num_points << ",\n  \"probe_rest\": [" << num(p.probe_rest.x())
      << ", " << num(p.probe_rest.y()) << ", " << num(p.probe_rest.z()) << "],\n"
      << "  \"probe_dofs\": [";
  bool first = true;
  for (int node : p.constraints.probe_nodes) {
    for (int c = 0; c < 3; ++c) {
      if (p.constraints.role[3 * node + c] != DofRole::kProbe) continue;
      out << (first ? "" : ", ") << "[" << node << ", " << c << "]";
      first = false;
    }
  }
  out << "]\n}\n";
  if (!out) throw InputError("cannot write " + file.string());
}

}  // namespace

bool ccx_needs_nlgeom(Law law) { return law != Law::kLinear; }

std::string ccx_material_cards(const MaterialConstants& c) {
  std::ostringstream s;
  auto bad = [&](const std::string& what) {
    return InputError("CalculiX export: material " + std::string(law_name(c.law)) + ": " + what);
  };
  switch (c.law) {
    case Law::kLinear:
    case Law::kStvk: {
      // *ELASTIC takes E, nu. With NLGEOM ccx uses it as S = D:E (second Piola-Kirchhoff stress
      // from the Lagrange strain), i.e. St. Venant-Kirchhoff; without NLGEOM it is Hooke's law.
      if (!(c.mu > 0) || !(c.lambda + c.mu > 0)) throw bad("needs mu > 0 and lambda + mu > 0");
      const double young = c.mu * (3 * c.lambda + 2 * c.mu) / (c.lambda + c.mu);
      const double poisson = c.lambda / (2 * (c.lambda + c.mu));
      if (!(poisson > -1 && poisson < 0.5)) throw bad("Poisson's ratio outside (-1, 0.5)");
      s << "*ELASTIC\n" << num(young) << ", " << num(poisson) << "\n";
      break;
    }
    case Law::kNeoHooke:
      // U = C10 (I1bar - 3) + (J - 1)^2 / D1; D1 = 0 would mean ccx's default compressibility.
      if (!(c.c10 > 0) || !(c.d1 > 0)) throw bad("needs c10 > 0 and d1 > 0");
      s << "*HYPERELASTIC, NEO HOOKE\n" << num(c.c10) << ", " << num(c.d1) << "\n";
      break;
    case Law::kMooney:
      // U = C10 (I1bar - 3) + C01 (I2bar - 3) + (J - 1)^2 / D1.
      if (!(c.c10 + c.c01 > 0) || !(c.d1 > 0)) throw bad("needs c10 + c01 > 0 and d1 > 0");
      s << "*HYPERELASTIC, MOONEY-RIVLIN\n"
        << num(c.c10) << ", " << num(c.c01) << ", " << num(c.d1) << "\n";
      break;
  }
  return s.str();
}

void write_ccx_deck(const Problem& p, const std::vector<Eigen::Vector3d>& probe_path,
                    const std::filesystem::path& dir, const CcxDeckOptions& options) {
  if (probe_path.empty() && !p.loads.has_force())
    throw InputError(deck_error(dir, "the probe path is empty"));
  if (options.increments_per_step < 1 || options.max_iterations < 2 ||
      !(options.residual_tolerance > 0) || !(options.correction_tolerance > 0)) {
    throw InputError(deck_error(dir, "bad deck options"));
  }
  if (!(p.unit > 0)) throw InputError(deck_error(dir, "mesh unit must be > 0"));
  check_mesh(p.mesh, dir);
  const DofSets sets = dof_sets(p, dir);
  const std::string material = ccx_material_cards(p.material);
  const bool nlgeom = ccx_needs_nlgeom(p.material.law);

  std::filesystem::create_directories(dir);
  std::ofstream out(dir / kCcxDeckFile);
  const Mesh& m = p.mesh;
  out << "** hapstate -> CalculiX cross-check deck (see docs/calculix.md)\n"
      << "** law " << law_name(p.material.law) << "; " << m.num_nodes() << " nodes, "
      << m.num_tets() << " C3D4; " << probe_path.size() << " path points\n"
      << "** lengths in metres (mesh units x " << num(p.unit) << "), forces in N, stresses in Pa\n"
      << "** node id = hapstate node id + 1, element id = hapstate tet id + 1\n"
      << "*HEADING\nhapstate cross-check of " << (m.source.empty() ? "a generated mesh" : m.source)
      << "\n";

  out << "*NODE, NSET=NALL\n";
  for (int i = 0; i < m.num_nodes(); ++i) {
    const Eigen::Vector3d x = m.nodes.col(i) * p.unit;
    out << i + 1 << ", " << num(x.x()) << ", " << num(x.y()) << ", " << num(x.z()) << "\n";
  }
  out << "** C3D4 node order as ours: det[n2-n1, n3-n1, n4-n1] > 0\n"
      << "*ELEMENT, TYPE=C3D4, ELSET=EALL\n";
  for (int e = 0; e < m.num_tets(); ++e) {
    out << e + 1;
    for (int k = 0; k < 4; ++k) out << ", " << m.tets(k, e) + 1;
    out << "\n";
  }

  out << "** node sets: FIXED_<c> hold component c at 0, PROBE_<c> follow the probe in c,\n"
      << "** PROBE = every grabbed node (its RF is printed)\n";
  for (int c = 0; c < 3; ++c) {
    if (!sets.fixed[c].empty()) write_node_set(out, set_name("FIXED", c), sets.fixed[c]);
    if (!sets.probe[c].empty()) write_node_set(out, set_name("PROBE", c), sets.probe[c]);
  }
  std::vector<int> probe_nodes = p.constraints.probe_nodes;
  std::sort(probe_nodes.begin(), probe_nodes.end());
  probe_nodes.erase(std::unique(probe_nodes.begin(), probe_nodes.end()), probe_nodes.end());
  if (!probe_nodes.empty()) write_node_set(out, "PROBE", probe_nodes);

  const bool gravity = p.loads.has_force();
  if (gravity && !(p.loads.density > 0 && p.loads.gravity.norm() > 0))
    throw InputError(deck_error(dir, "the body force has no density and gravity to export"));
  if (gravity && p.rest_m.size() != 3 * m.num_nodes())
    throw InputError(deck_error(dir, "gravity without the loaded rest state (Problem::rest_m)"));
  out << "*MATERIAL, NAME=TISSUE\n" << material;
  if (gravity) out << "*DENSITY\n" << num(p.loads.density) << "\n";
  out << "*SOLID SECTION, ELSET=EALL, MATERIAL=TISSUE\n";
  if (p.loads.has_springs()) {
    // A support: one grounded linear spring (SPRING1) per supported DOF, N/m.
    out << "** supports ([[support]]): SPRING1 elements, one per supported DOF\n";
    int id = m.num_tets();
    for (int d = 0; d < 3 * m.num_nodes(); ++d) {
      const double k = p.loads.spring[d];
      if (!(k > 0) || p.constraints.role[d] == DofRole::kFixed) continue;
      ++id;
      // ccx reads a stiffness written as an integer ("10") as no data: always a decimal point.
      std::string stiffness = num(k);
      if (stiffness.find_first_of(".eE") == std::string::npos) stiffness += ".";
      out << "*ELEMENT, TYPE=SPRING1, ELSET=S" << id << "\n"
          << id << ", " << d / 3 + 1 << "\n*SPRING, ELSET=S" << id << "\n"
          << d % 3 + 1 << "\n"
          << stiffness << "\n";
    }
  }
  bool any_fixed = false;
  for (int c = 0; c < 3; ++c) any_fixed = any_fixed || !sets.fixed[c].empty();
  if (any_fixed) {
    out << "** fixed DOFs, held at 0 in every step\n*BOUNDARY\n";
    for (int c = 0; c < 3; ++c) {
      if (!sets.fixed[c].empty())
        out << set_name("FIXED", c) << ", " << c + 1 << ", " << c + 1 << "\n";
    }
  }

  const std::string step = step_cards(options, nlgeom);
  // With gravity the probe DOFs are prescribed node by node: their rest displacement + t.
  const auto probe_boundary = [&](const Eigen::Vector3d& t) {
    out << "*BOUNDARY\n";
    for (int c = 0; c < 3; ++c)
      for (int node : sets.probe[c])
        out << node + 1 << ", " << c + 1 << ", " << c + 1 << ", "
            << num(p.rest_m[3 * node + c] + t[c]) << "\n";
  };
  const std::string prints =
      "*NODE PRINT, NSET=NALL, FREQUENCY=" + std::to_string(kPrintOnlyStepEnd) + "\nU\n" +
      (probe_nodes.empty() ? "" : "*NODE PRINT, NSET=PROBE, TOTALS=YES\nRF\n") +
      (options.write_frd ? "*NODE FILE\nU, RF\n" : "");
  if (gravity) {
    const double g = p.loads.gravity.norm();
    const Eigen::Vector3d dir_g = p.loads.gravity / g;
    // The whole weight at once is a large load (a soft organ may sag by much of its size): ccx
    // may cut its increments back here, whatever the path's steps do.
    CcxDeckOptions rest = options;
    rest.allow_cutbacks = true;
    // A deck with a path holds the probe nodes at our rest state's displacement from the first
    // step on: ccx ramps a newly prescribed displacement from zero, not from where the node is,
    // which undoes the sag within the first increment of a later step and diverges. Their RF
    // there must then be their own weight (the felt force zero): the check that our rest state
    // is an equilibrium of the free body. Without a path the probe nodes stay free.
    const bool hold = !probe_path.empty();
    out << "**\n** the loaded rest state: gravity, the probe nodes "
        << (hold ? "held at hapstate's rest displacement" : "free") << "; step time ends at 1\n"
        << step_cards(rest, nlgeom) << "*DLOAD\nEALL, GRAV, " << num(g) << ", " << num(dir_g.x())
        << ", " << num(dir_g.y()) << ", " << num(dir_g.z()) << "\n";
    if (hold) probe_boundary(Eigen::Vector3d::Zero());
    out << prints << "*END STEP\n";
  }
  const int first_time = ccx_first_point_time(p);
  for (std::size_t k = 0; k < probe_path.size(); ++k) {
    const Eigen::Vector3d& pk = probe_path[k];
    const Eigen::Vector3d t = (pk - p.probe_rest) * p.unit;
    out << "**\n** path point " << k + 1 << ": probe at (" << num(pk.x()) << ", " << num(pk.y())
        << ", " << num(pk.z()) << ") mesh units, t = (" << num(t.x()) << ", " << num(t.y()) << ", "
        << num(t.z()) << ") m" << (gravity ? " from the rest state" : "") << "; step time ends at "
        << static_cast<int>(k) + first_time << "\n"
        << step;
    bool any_probe = false;
    for (int c = 0; c < 3; ++c) any_probe = any_probe || !sets.probe[c].empty();
    if (any_probe && !gravity) {
      out << "*BOUNDARY\n";
      for (int c = 0; c < 3; ++c) {
        if (sets.probe[c].empty()) continue;
        out << set_name("PROBE", c) << ", " << c + 1 << ", " << c + 1 << ", " << num(t[c]) << "\n";
      }
    } else if (any_probe) {
      probe_boundary(t);
    }
    out << prints << "*END STEP\n";
  }
  if (!out) throw InputError(deck_error(dir, "cannot write the deck files"));
  write_probe_path(probe_path, dir / kCcxPathFile);  // header only for the rest step alone
  write_meta(p, static_cast<int>(probe_path.size()), dir / kCcxMetaFile);
}

}  // namespace hapstate
