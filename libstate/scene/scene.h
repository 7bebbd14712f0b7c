// The scene file (docs/scene.md) as a plain, validated struct.
// Lengths are in mesh units; `mesh.unit` converts them to metres. Forces in N, stresses in Pa.
#pragma once

#include "material/material.h"
#include "problem/solver_options.h"

#include <Eigen/Core>

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace hapstate {

// Which of x, y, z a selector acts on.
using DofMask = std::array<bool, 3>;

// Axis-aligned box, closed: a point p is inside iff min <= p <= max componentwise. min < max.
struct Box {
  Eigen::Vector3d min = Eigen::Vector3d::Zero();
  Eigen::Vector3d max = Eigen::Vector3d::Zero();
};

struct SceneMesh {
  std::filesystem::path file;  // resolved against the scene file's folder
  double unit = 1.0;           // metres per mesh unit, > 0
};

// Material as written: the law plus either young+poisson or the law's own constants
// (linear/stvk: mu+lambda; neohooke: c10+d1; mooney: c10+c01+d1). Exactly one set is present.
struct SceneMaterial {
  Law law = Law::kStvk;
  std::optional<double> young, poisson;  // Pa, -
  std::optional<double> mu, lambda;      // Pa
  std::optional<double> c10, c01, d1;    // Pa, Pa, 1/Pa
  std::optional<double> density;         // kg/m^3 (needed by gravity only)
};

// [loads]: the body force. Gravity acts on the mesh as drawn (a dead load: the weight of each
// tet's mass, density x reference volume) in the mesh's axes.
struct SceneLoads {
  std::optional<Eigen::Vector3d> gravity;  // m/s^2; needs material.density
  int line = 0;                            // line of the [loads] header
};

// [[fixed]] selectors: exactly one per table.
struct BoxSelector {
  Box box;
};
struct PlaneSelector {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // non-zero, not necessarily unit
  std::optional<double> tolerance;  // mesh units; default 1e-6 x mesh bounding-box diagonal
};
struct GroupSelector {
  std::string name;
};  // a physical group of the mesh
struct NodesSelector {
  std::filesystem::path file;
};  // resolved against the scene folder

struct FixedSelector {
  std::variant<BoxSelector, PlaneSelector, GroupSelector, NodesSelector> where;
  DofMask dofs{true, true, true};
  int line = 0;  // line of the [[fixed]] header in the scene file (0 if unknown)
};

// [[support]]: an elastic foundation over the selected surface (the surface triangles whose
// three corners are selected), pulling it towards its position in the mesh as drawn with
// `stiffness` N/m^3 (pressure per metre of displacement), in the components of `where.dofs`.
struct SupportSelector {
  FixedSelector where;
  double stiffness = 0;  // N/m^3, > 0
};

enum class ProbeMode { kGrab, kContact };

// [probe]. Grab: exactly one of `point` (nearest node), `point` + `radius` (surface patch),
// `nodes_file` or `group`. Contact: `point` (sphere centre at rest) and `radius` (sphere radius).
struct SceneProbe {
  ProbeMode mode = ProbeMode::kGrab;
  std::optional<Eigen::Vector3d> point;
  std::optional<double> radius;  // > 0
  std::optional<std::filesystem::path> nodes_file;
  std::optional<std::string> group;     // grab: every node of this physical group
  DofMask dofs{true, true, true};       // grab: components that follow the probe
  Friction friction = Friction::kNone;  // contact: probe.friction
  double max_force = 0;                 // N, > 0
  int line = 0;                         // line of the [probe] header
};

// [grid]: `spacing` or `dims` (then `box` is required). Without `box` the workspace is
// 4 spacings each way around the probe's rest position (resolved by the grid stage).
struct SceneGrid {
  std::optional<Eigen::Vector3d> spacing;  // per axis, > 0 (a number gives three equal)
  std::optional<std::array<int, 3>> dims;  // check-points per axis, >= 2
  std::optional<Box> box;
  // > 0: the refine stage refines a cell whose estimated interpolation error exceeds it times
  // the largest force in the cell (default 1e-3; docs/scene.md).
  std::optional<double> refine_tolerance;
  // 1, 2 or 3: how far the refine stage refines a flagged cell, 1 the quarter-spacing lattice, 2
  // also the eighth-spacing one, 3 also sixteenth-spacing points in its eighth cells above the
  // tolerance (default: run_refine's default_refine_depth).
  std::optional<int> refine_depth;
};

// [levels]: when two configurations at a check-point are the same level. See level_tolerances.
struct SceneLevels {
  std::optional<double> displacement_tolerance;  // mesh units, > 0
  std::optional<double> force_tolerance;         // N, > 0
};

// [certify]: the certificate's experiment (hapstate-certify, docs/certificate.md).
struct SceneCertify {
  int paths = 20;  // seeded random paths, >= 1
  int steps = 30;  // steps per path, >= 2
};

struct Scene {
  std::filesystem::path path;  // the scene file as given (messages, relative paths)
  std::string text;            // the raw scene text, byte for byte (stored and hashed later)
  SceneMesh mesh;
  SceneMaterial material;
  std::vector<FixedSelector> fixed;  // union of all selectors is fixed (may be empty)
  std::vector<SupportSelector> supports;
  SceneLoads loads;
  bool has_probe = true;  // false only for a scene parsed with require_probe = false and no [probe]
  SceneProbe probe;
  SceneGrid grid;
  SolverOptions solver;
  SceneLevels levels;
  SceneCertify certify;
};

struct SceneParseOptions {
  // Check that mesh.file and every nodes file exist. Off when re-reading a stored scene
  // whose files are not needed (e.g. the text kept in the catalogue).
  bool check_files = true;
  // [probe] and [grid] are required (off: hapstate-solve --rest, the loaded rest state alone).
  bool require_probe = true;
};

// Parses and validates scene text. `path` is used in messages and to resolve relative file
// names (against path's folder). Every problem is collected; if any, throws one InputError
// whose message has one line per problem: "path:LINE: key 'a.b' = value: what is wrong".
// A TOML syntax error throws "path:LINE:COL: <toml++ description>".
Scene parse_scene(const std::string& text, const std::filesystem::path& path,
                  const SceneParseOptions& options = {});

// Reads `file` and parses it with parse_scene. Throws InputError if it cannot be read.
Scene load_scene(const std::filesystem::path& file, const SceneParseOptions& options = {});

// Level tolerances with the documented defaults applied: displacement 1e-2 x the smallest
// grid spacing (mesh units), force 1e-2 x probe.max_force (N).
struct LevelTolerances {
  double displacement = 0;
  double force = 0;
};
LevelTolerances level_tolerances(const Scene& scene);

// The smallest grid spacing in mesh units: grid.spacing, or box extent / (dims - 1).
double smallest_grid_spacing(const SceneGrid& grid);

}  // namespace hapstate
