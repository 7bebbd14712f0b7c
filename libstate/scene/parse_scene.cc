// parse_scene / load_scene: TOML text -> validated Scene (docs/scene.md is the key reference).
#include "scene/diagnostics.h"
#include "scene/scene.h"
#include "scene/toml_reader.hpp"
#include "util/error.h"

#include <algorithm>
#include <fstream>
#include <sstream>
#include <type_traits>

namespace hapstate {
namespace {

using scene_detail::closed;
using scene_detail::Interval;
using scene_detail::line_of;
using scene_detail::non_negative;
using scene_detail::open;
using scene_detail::positive;
using scene_detail::TableReader;
using scene_detail::type_phrase;

constexpr int kMaxSubsteps = 10000;
constexpr int kMaxIterations = 1000;
constexpr int kMaxCutbacks = 50;

struct Context {
  std::filesystem::path scene_path;
  SceneParseOptions options;
};

std::filesystem::path resolve(const Context& context, const std::string& file) {
  const std::filesystem::path p(file);
  if (p.is_absolute()) return p.lexically_normal();
  return (context.scene_path.parent_path() / p).lexically_normal();
}

// Reads a file-name key: non-empty string, resolved against the scene folder, optionally
// checked to exist.
std::optional<std::filesystem::path> read_file_key(const TableReader& r, std::string_view key,
                                                   const Context& context) {
  const auto name = r.string(key);
  if (!name) return std::nullopt;
  if (name->empty()) {
    r.bad(key, "must be a file name");
    return std::nullopt;
  }
  auto path = resolve(context, *name);
  if (context.options.check_files) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) {
      r.bad(key, "file not found: " + path.string());
      return std::nullopt;
    }
  }
  return path;
}

SceneMesh parse_mesh(const TableReader& r, const Context& context) {
  r.allow_only({"file", "unit"});
  SceneMesh mesh;
  if (!r.has("file")) r.missing("file");
  if (auto file = read_file_key(r, "file", context)) mesh.file = *file;
  if (auto unit = r.number("unit", positive())) mesh.unit = *unit;
  return mesh;
}

std::optional<Law> parse_law(std::string_view name) {
  if (name == "linear") return Law::kLinear;
  if (name == "stvk") return Law::kStvk;
  if (name == "neohooke") return Law::kNeoHooke;
  if (name == "mooney") return Law::kMooney;
  return std::nullopt;
}

// The law's own constants, in the order they are listed in messages.
std::vector<std::string_view> own_constants(Law law) {
  switch (law) {
    case Law::kLinear:
    case Law::kStvk:
      return {"mu", "lambda"};
    case Law::kNeoHooke:
      return {"c10", "d1"};
    case Law::kMooney:
      return {"c10", "c01", "d1"};
  }
  return {};
}

std::string join_and(const std::vector<std::string_view>& names) {
  std::string out;
  for (size_t i = 0; i < names.size(); ++i) {
    if (i > 0) out += i + 1 == names.size() ? " and " : ", ";
    out += names[i];
  }
  return out;
}

SceneMaterial parse_material(const TableReader& r) {
  r.allow_only({"law", "young", "poisson", "mu", "lambda", "c10", "c01", "d1", "density"});
  SceneMaterial m;
  m.density = r.number("density", positive());
  std::optional<Law> law;
  if (!r.has("law")) {
    r.missing("law", "linear, stvk, neohooke or mooney");
  } else if (auto name = r.string("law")) {
    law = parse_law(*name);
    if (!law) r.bad("law", "must be one of linear, stvk, neohooke, mooney");
  }
  if (law) m.law = *law;

  // Ranges first, independently of the law.
  m.young = r.number("young", positive());
  m.poisson = r.number("poisson", open(-1.0, 0.5));
  m.mu = r.number("mu", positive());
  m.lambda = r.number("lambda");
  m.c10 = r.number("c10", positive());
  m.c01 = r.number("c01", non_negative());
  m.d1 = r.number("d1", positive());
  if (m.mu && m.lambda && !(*m.lambda + 2.0 / 3.0 * *m.mu > 0)) {
    r.bad("lambda", "must be > -2/3 mu (a positive bulk modulus)");
    m.lambda.reset();
  }
  if (!law) return m;

  // Which set was given: young + poisson, or the law's own constants, never both.
  const auto own = own_constants(*law);
  const std::string choice = "give young and poisson, or " + join_and(own);
  for (std::string_view key : {"mu", "lambda", "c10", "c01", "d1"}) {
    if (r.has(key) && std::find(own.begin(), own.end(), key) == own.end()) {
      r.bad(key, "does not apply to law '" + *r.string("law") + "' (" + choice + ")");
    }
  }
  const bool has_young_poisson = r.has("young") || r.has("poisson");
  bool has_own = false;
  for (std::string_view key : own) has_own = has_own || r.has(key);
  if (has_young_poisson && has_own) {
    for (std::string_view key : own) {
      if (r.has(key)) r.bad(key, "cannot be combined with young/poisson (" + choice + ")");
    }
  } else if (has_young_poisson) {
    for (std::string_view key : {"young", "poisson"}) {
      if (!r.has(key)) r.missing(key, "young and poisson go together");
    }
  } else if (has_own) {
    for (std::string_view key : own) {
      if (!r.has(key)) r.missing(key, "law '" + *r.string("law") + "' needs " + join_and(own));
    }
  } else {
    r.diagnostics().add(r.line(), "missing material constants in [" + r.name() + "]: " + choice);
  }
  return m;
}

std::optional<PlaneSelector> parse_plane(const TableReader& r) {
  r.allow_only({"point", "normal", "tolerance"});
  PlaneSelector plane;
  const auto point = r.point("point");
  if (!r.has("point")) r.missing("point");
  auto normal = r.point("normal");
  if (!r.has("normal")) r.missing("normal");
  if (normal && normal->norm() == 0.0) {
    r.bad("normal", "must be non-zero");
    normal.reset();
  }
  plane.tolerance = r.number("tolerance", positive());
  if (!point || !normal || (r.has("tolerance") && !plane.tolerance)) return std::nullopt;
  plane.point = *point;
  plane.normal = *normal;
  return plane;
}

// A [[fixed]] or [[support]] selector (`kind`); a support's stiffness is read by the caller.
std::optional<FixedSelector> parse_fixed(const TableReader& r, const Context& context,
                                         std::string_view kind = "fixed") {
  if (kind == "support")
    r.allow_only({"box", "plane", "group", "nodes", "dofs", "stiffness"});
  else
    r.allow_only({"box", "plane", "group", "nodes", "dofs"});
  FixedSelector selector;
  selector.line = r.line();
  bool ok = true;
  std::vector<std::string_view> given;
  for (std::string_view key : {"box", "plane", "group", "nodes"}) {
    if (r.has(key)) given.push_back(key);
  }
  if (given.size() != 1) {
    std::string message = "[[" + std::string(kind) + "]] table '" + r.name() +
                          "': give exactly one of box, plane, group, nodes";
    if (!given.empty()) message += " (got " + join_and(given) + ")";
    r.diagnostics().add(r.line(), message);
    ok = false;
  }
  if (r.has("box")) {
    if (auto box = r.box("box"))
      selector.where = BoxSelector{*box};
    else
      ok = false;
  }
  if (r.has("plane")) {
    const toml::table* t = r.table("plane");
    std::optional<PlaneSelector> plane;
    if (t) plane = parse_plane(TableReader(*t, r.full_name("plane"), r.diagnostics()));
    if (plane)
      selector.where = *plane;
    else
      ok = false;
  }
  if (r.has("group")) {
    const auto name = r.string("group");
    if (name && name->empty()) r.bad("group", "must name a physical group of the mesh");
    if (name && !name->empty())
      selector.where = GroupSelector{*name};
    else
      ok = false;
  }
  if (r.has("nodes")) {
    if (auto file = read_file_key(r, "nodes", context))
      selector.where = NodesSelector{*file};
    else
      ok = false;
  }
  if (auto dofs = r.dofs("dofs")) selector.dofs = *dofs;
  if (!ok) return std::nullopt;
  return selector;
}

// Every table of the array of tables `name` ([[name]] headers) through `parse_one`, which
// returns std::optional<T> (nothing for a table with problems, already reported).
template <class ParseOne>
auto parse_table_array(const TableReader& root, const std::string& name, ParseOne parse_one) {
  using Item = typename std::invoke_result_t<ParseOne, const TableReader&>::value_type;
  std::vector<Item> list;
  const toml::node* node = root.get(name);
  if (node == nullptr) return list;
  const auto* array = node->as_array();
  if (array == nullptr || !array->is_array_of_tables()) {
    root.bad(name, "expected an array of tables ([[" + name + "]] headers), got " +
                       (array ? std::string("an array of values") : type_phrase(*node)));
    return list;
  }
  for (size_t i = 0; i < array->size(); ++i) {
    const TableReader r(*array->get(i)->as_table(), name + "[" + std::to_string(i) + "]",
                        root.diagnostics());
    if (auto item = parse_one(r)) list.push_back(std::move(*item));
  }
  return list;
}

std::vector<FixedSelector> parse_fixed_list(const TableReader& root, const Context& context) {
  return parse_table_array(root, "fixed",
                           [&](const TableReader& r) { return parse_fixed(r, context); });
}

std::vector<SupportSelector> parse_support_list(const TableReader& root, const Context& context) {
  return parse_table_array(root, "support",
                           [&](const TableReader& r) -> std::optional<SupportSelector> {
                             if (!r.has("stiffness"))
                               r.missing("stiffness",
                                         "N/m^3, the supporting pressure per metre of "
                                         "displacement");
                             const auto stiffness = r.number("stiffness", positive());
                             auto selector = parse_fixed(r, context, "support");
                             if (!selector || !stiffness) return std::nullopt;
                             return SupportSelector{std::move(*selector), *stiffness};
                           });
}

SceneLoads parse_loads(const TableReader& r) {
  r.allow_only({"gravity"});
  SceneLoads loads;
  loads.line = r.line();
  if (!r.has("gravity")) r.missing("gravity", "[gx, gy, gz] in m/s^2, in the mesh's axes");
  loads.gravity = r.point("gravity");
  if (loads.gravity && loads.gravity->norm() == 0.0) {
    r.bad("gravity", "must be non-zero (leave [loads] out for a body without weight)");
    loads.gravity.reset();
  }
  return loads;
}

SceneProbe parse_probe(const TableReader& r, const Context& context) {
  r.allow_only({"mode", "point", "radius", "nodes", "group", "dofs", "max_force", "friction"});
  SceneProbe probe;
  probe.line = r.line();
  bool mode_ok = true;  // mode absent (grab) or valid
  if (r.has("mode")) {
    const auto name = r.string("mode");
    mode_ok = name && (*name == "grab" || *name == "contact");
    if (name && !mode_ok) r.bad("mode", "must be one of grab, contact");
    if (mode_ok) probe.mode = *name == "grab" ? ProbeMode::kGrab : ProbeMode::kContact;
  }
  if (r.has("friction")) {
    const auto name = r.string("friction");
    if (name && *name != "none" && *name != "stick")
      r.bad("friction", "must be one of none (frictionless sliding), stick");
    else if (name)
      probe.friction = *name == "none" ? Friction::kNone : Friction::kStick;
  }
  probe.point = r.point("point");
  probe.radius = r.number("radius", positive());
  if (r.has("nodes")) probe.nodes_file = read_file_key(r, "nodes", context);
  probe.group = r.string("group");
  if (auto dofs = r.dofs("dofs")) probe.dofs = *dofs;
  if (!r.has("max_force")) r.missing("max_force", "N, the device force limit");
  if (auto f = r.number("max_force", positive())) probe.max_force = *f;

  if (mode_ok && probe.mode == ProbeMode::kGrab) {
    const int ways = int(r.has("nodes")) + int(r.has("group")) + int(r.has("point"));
    if (ways > 1) {
      r.bad(r.has("nodes") ? "nodes" : "group",
            "give exactly one of point (with an optional radius), nodes or group");
    } else if (ways == 0) {
      r.missing("point", "grab needs point, point and radius, nodes, or group");
    } else if (r.has("radius") && !r.has("point")) {
      r.bad("radius", "a grab radius needs point (the patch centre)");
    }
  } else if (mode_ok && probe.mode == ProbeMode::kContact) {
    if (!r.has("point")) r.missing("point", "contact: the sphere centre at rest");
    if (!r.has("radius")) r.missing("radius", "contact: the sphere radius");
    if (r.has("nodes")) r.bad("nodes", "only allowed with mode = \"grab\"");
    if (r.has("group")) r.bad("group", "only allowed with mode = \"grab\"");
    if (r.has("dofs")) r.bad("dofs", "only allowed with mode = \"grab\"");
  }
  if (mode_ok && probe.mode == ProbeMode::kGrab && r.has("friction"))
    r.bad("friction", "only allowed with mode = \"contact\"");
  return probe;
}

std::optional<std::array<int, 3>> read_dims(const TableReader& r) {
  const toml::node* node = r.get("dims");
  if (node == nullptr) return std::nullopt;
  const auto* array = node->as_array();
  bool ok = array && array->size() == 3;
  std::array<int, 3> dims{};
  for (size_t k = 0; ok && k < 3; ++k) {
    const auto* i = array->get(k)->as_integer();
    ok = i != nullptr;
    if (ok && (i->get() < 2 || i->get() > 1'000'000)) {
      r.bad("dims", "every count must be in [2, 1000000]");
      return std::nullopt;
    }
    if (ok) dims[k] = static_cast<int>(i->get());
  }
  if (!ok) {
    r.bad("dims", "expected an array of 3 integers [nx, ny, nz], got " +
                      (array ? std::string("an array of ") + std::to_string(array->size()) +
                                   " element(s) or non-integers"
                             : type_phrase(*node)));
    return std::nullopt;
  }
  return dims;
}

SceneGrid parse_grid(const TableReader& r) {
  r.allow_only({"spacing", "dims", "box", "refine_tolerance", "refine_depth"});
  SceneGrid grid;
  grid.refine_tolerance = r.number("refine_tolerance", positive());
  grid.refine_depth = r.integer("refine_depth", closed(1, 3));
  if (const toml::node* node = r.get("spacing")) {
    if (node->is_array()) {
      auto h = r.point("spacing");
      if (h && !(h->minCoeff() > 0)) {
        r.bad("spacing", "every component must be > 0");
        h.reset();
      }
      grid.spacing = h;
    } else if (auto h = r.number("spacing", positive())) {
      grid.spacing = Eigen::Vector3d::Constant(*h);
    }
  }
  grid.dims = read_dims(r);
  grid.box = r.box("box");
  if (r.has("spacing") && r.has("dims")) {
    r.bad("dims", "give either spacing or dims, not both");
  } else if (!r.has("spacing") && !r.has("dims")) {
    r.missing("spacing", "or dims");
  } else if (r.has("dims") && !r.has("box")) {
    r.missing("box", "required with dims");
  }
  return grid;
}

SolverOptions parse_solver(const TableReader& r) {
  r.allow_only({"substeps", "tolerance", "absolute_tolerance", "max_iterations", "max_cutbacks"});
  SolverOptions s;
  if (auto v = r.integer("substeps", closed(1, kMaxSubsteps))) s.substeps = *v;
  if (auto v = r.number("tolerance", open(0.0, 1.0))) s.tolerance = *v;
  if (auto v = r.number("absolute_tolerance", non_negative())) s.absolute_tolerance = *v;
  if (auto v = r.integer("max_iterations", closed(1, kMaxIterations))) s.max_iterations = *v;
  if (auto v = r.integer("max_cutbacks", closed(0, kMaxCutbacks))) s.max_cutbacks = *v;
  return s;
}

SceneLevels parse_levels(const TableReader& r) {
  r.allow_only({"displacement_tolerance", "force_tolerance"});
  SceneLevels levels;
  levels.displacement_tolerance = r.number("displacement_tolerance", positive());
  levels.force_tolerance = r.number("force_tolerance", positive());
  return levels;
}

SceneCertify parse_certify(const TableReader& r) {
  r.allow_only({"paths", "steps"});
  SceneCertify c;
  if (auto v = r.integer("paths", closed(1, 100000))) c.paths = *v;
  if (auto v = r.integer("steps", closed(2, 100000))) c.steps = *v;
  return c;
}

// Applies `parse` to the sub-table `name` of the root, or records its absence if required.
template <class Parse>
void section(const TableReader& root, std::string_view name, bool required, Parse parse) {
  if (const toml::table* t = root.table(name)) {
    parse(TableReader(*t, std::string(name), root.diagnostics()));
  } else if (required && !root.has(name)) {
    root.diagnostics().add(0, "missing table [" + std::string(name) + "]");
  }
}

}  // namespace

Scene parse_scene(const std::string& text, const std::filesystem::path& path,
                  const SceneParseOptions& options) {
  const std::string file = path.string();
  toml::table root_table;
  try {
    root_table = toml::parse(text, file);
  } catch (const toml::parse_error& e) {
    const auto& where = e.source().begin;
    throw InputError(file + ":" + std::to_string(where.line) + ":" + std::to_string(where.column) +
                     ": " + std::string(e.description()));
  }

  Scene scene;
  scene.path = path;
  scene.text = text;
  const Context context{path, options};
  Diagnostics diagnostics(file);
  const TableReader root(root_table, "", diagnostics);
  root.allow_only({"mesh", "material", "fixed", "support", "loads", "probe", "grid", "solver",
                   "levels", "certify"});
  section(root, "mesh", true, [&](const TableReader& r) { scene.mesh = parse_mesh(r, context); });
  section(root, "material", true,
          [&](const TableReader& r) { scene.material = parse_material(r); });
  scene.fixed = parse_fixed_list(root, context);
  scene.supports = parse_support_list(root, context);
  section(root, "loads", false, [&](const TableReader& r) { scene.loads = parse_loads(r); });
  if (scene.loads.gravity && !scene.material.density) {
    diagnostics.add(scene.loads.line,
                    "key 'loads.gravity' needs 'material.density' (kg/m^3): the body's weight is "
                    "density x volume x gravity");
  }
  scene.has_probe = root.has("probe");
  section(root, "probe", options.require_probe,
          [&](const TableReader& r) { scene.probe = parse_probe(r, context); });
  section(root, "grid", options.require_probe,
          [&](const TableReader& r) { scene.grid = parse_grid(r); });
  section(root, "solver", false, [&](const TableReader& r) { scene.solver = parse_solver(r); });
  section(root, "levels", false, [&](const TableReader& r) { scene.levels = parse_levels(r); });
  section(root, "certify", false, [&](const TableReader& r) { scene.certify = parse_certify(r); });
  diagnostics.throw_if_any();
  return scene;
}

Scene load_scene(const std::filesystem::path& file, const SceneParseOptions& options) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string() + ": cannot open scene file");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw InputError(file.string() + ": cannot read scene file");
  return parse_scene(text.str(), file, options);
}

}  // namespace hapstate
