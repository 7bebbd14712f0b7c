// hapstate-inspect checkpoint, config, transitions.
#include "blobs/blob_store.h"
#include "maintenance/inspect_common.hpp"
#include "util/error.h"

#include <cmath>
#include <sstream>

namespace hapstate {

using namespace inspect_detail;

namespace {

double norm3(const std::array<double, 3>& v) {
  return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

Json checkpoint_json(const Checkpoint& c) {
  return {{"id", c.id.value()},
          {"ijk", c.ijk},
          {"position", c.position},
          {"class", checkpoint_class_name(c.classification)}};
}

std::string ijk_text(const Json& ijk) {
  std::ostringstream s;
  s << '(' << ijk[0] << ", " << ijk[1] << ", " << ijk[2] << ')';
  return s.str();
}

std::string vec_text(const Json& v) {
  std::ostringstream s;
  s << '(';
  for (std::size_t i = 0; i < v.size(); ++i) s << (i ? ", " : "") << num(v[i].get<double>());
  s << ')';
  return s.str();
}

Configuration read_config(Catalogue& cat, ConfigId id, const StateDir& dir) {
  if (!cat.exists_configuration(id)) {
    throw InputError(dir.catalogue().string() + ": no configuration with id " +
                     std::to_string(id.value()));
  }
  return cat.read_configuration(id);
}

InspectOutput checkpoint_output(Catalogue& cat, const Checkpoint& cp) {
  Json j;
  j["checkpoint"] = checkpoint_json(cp);
  Json configs = Json::array();
  for (const Configuration& c : cat.configurations_at(cp.id)) {
    configs.push_back({{"id", c.id.value()},
                       {"level", c.level.value()},
                       {"wave", c.wave},
                       {"status", config_status_name(c.status)},
                       {"expandable", c.expandable},
                       {"force", c.force},
                       {"force_norm", norm3(c.force)},
                       {"transitions", cat.transitions_of(c.id).size()}});
  }
  j["configurations"] = configs;

  std::ostringstream s;
  s << "check-point " << cp.id.value() << " " << ijk_text(j["checkpoint"]["ijk"]) << " at "
    << vec_text(j["checkpoint"]["position"]) << ", " << checkpoint_class_name(cp.classification)
    << ", " << configs.size() << " configurations\n";
  for (const auto& c : configs) {
    s << "  level " << c["level"] << ": config " << c["id"] << ", wave " << c["wave"] << ", "
      << c["status"].get<std::string>() << (c["expandable"].get<bool>() ? ", expandable" : "")
      << ", force " << vec_text(c["force"]) << " N (|F| " << num(c["force_norm"].get<double>())
      << "), " << c["transitions"] << "/26 transitions\n";
  }
  return {dump(j), s.str()};
}

}  // namespace

InspectOutput inspect_checkpoint(const StateDir& dir, const std::array<int, 3>& ijk) {
  Catalogue cat = open_read_only(dir);
  const auto cp = cat.find_checkpoint(ijk);
  if (!cp) {
    throw InputError(dir.catalogue().string() + ": no check-point (" + std::to_string(ijk[0]) +
                     ", " + std::to_string(ijk[1]) + ", " + std::to_string(ijk[2]) + ")");
  }
  return checkpoint_output(cat, *cp);
}

InspectOutput inspect_checkpoint(const StateDir& dir, CheckpointId id) {
  Catalogue cat = open_read_only(dir);
  if (!cat.exists_checkpoint(id)) {
    throw InputError(dir.catalogue().string() + ": no check-point with id " +
                     std::to_string(id.value()));
  }
  return checkpoint_output(cat, cat.read_checkpoint(id));
}

InspectOutput inspect_config(const StateDir& dir, ConfigId id) {
  Catalogue cat = open_read_only(dir);
  const Configuration c = read_config(cat, id, dir);
  Json j;
  j["id"] = c.id.value();
  j["checkpoint"] = checkpoint_json(cat.read_checkpoint(c.checkpoint));
  j["level"] = c.level.value();
  j["wave"] = c.wave;
  j["force"] = c.force;
  j["force_norm"] = norm3(c.force);
  j["stiffness"] = Json::array({{c.stiffness[0], c.stiffness[1], c.stiffness[2]},
                                {c.stiffness[3], c.stiffness[4], c.stiffness[5]},
                                {c.stiffness[6], c.stiffness[7], c.stiffness[8]}});
  j["expandable"] = c.expandable;
  j["status"] = config_status_name(c.status);
  if (c.blob) {
    Json vectors = Json::array();
    BlobStore blobs(dir.blobs());
    for (const std::string& v : blobs.list_vectors(c.blob->segment)) {
      if (v.rfind(c.blob->name + "/", 0) == 0) {
        vectors.push_back({{"name", v}, {"length", blobs.size_of(c.blob->segment, v)}});
      }
    }
    j["blob"] = {{"segment", c.blob->segment.value},
                 {"name", c.blob->name},
                 {"file", (dir.blobs() / segment_file_name(c.blob->segment)).string()},
                 {"vectors", vectors}};
  } else {
    j["blob"] = nullptr;
  }
  j["summary"] = c.summary;
  Json t = {{"decided", 0}, {"reached", 0}, {"outside_grid", 0}, {"failed", 0}};
  for (const Transition& tr : cat.transitions_of(c.id)) {
    t["decided"] = t["decided"].get<int>() + 1;
    const char* name = transition_outcome_name(tr.outcome);
    t[name] = t[name].get<int>() + 1;
  }
  j["transitions"] = t;
  j["incoming_transitions"] = query_int(
      cat, "SELECT count(*) FROM transition WHERE target = " + std::to_string(id.value()));

  std::ostringstream s;
  s << "configuration " << c.id.value() << ": check-point " << c.checkpoint.value() << " "
    << ijk_text(j["checkpoint"]["ijk"]) << ", level " << c.level.value() << ", wave " << c.wave
    << "\n  status " << config_status_name(c.status)
    << (c.expandable ? ", expandable" : ", not expandable") << "\n  force " << vec_text(j["force"])
    << " N, |F| " << num(norm3(c.force))
    << " N (felt by the user)\n  stiffness d(force felt)/d(probe position), N per mesh unit (a "
       "negative diagonal: the body pushes back)\n";
  for (const auto& row : j["stiffness"]) s << "    " << vec_text(row) << "\n";
  if (c.blob) {
    s << "  blob " << j["blob"]["file"].get<std::string>() << " group " << c.blob->name << ":";
    for (const auto& v : j["blob"]["vectors"])
      s << " " << v["name"].get<std::string>() << "[" << v["length"] << "]";
    s << "\n";
  } else {
    s << "  blob: none (zero state)\n";
  }
  s << "  transitions: " << t["decided"] << "/26 decided (" << t["reached"] << " reached, "
    << t["outside_grid"] << " outside, " << t["failed"] << " failed); " << j["incoming_transitions"]
    << " lead here\n";
  return {dump(j), s.str()};
}

InspectOutput inspect_transitions(const StateDir& dir, ConfigId id) {
  Catalogue cat = open_read_only(dir);
  const Configuration c = read_config(cat, id, dir);
  std::array<std::optional<Transition>, Direction::kCount> by_direction;
  for (Transition& t : cat.transitions_of(id)) {
    const int d = t.direction.index();
    by_direction[d] = std::move(t);
  }
  Json list = Json::array();
  std::ostringstream s;
  s << "configuration " << id.value() << " (check-point " << c.checkpoint.value() << ", level "
    << c.level.value() << "):\n"
    << "  dir  offset      outcome       target  level  substeps  iters  factors  residual    "
       "wall_ms  reason\n";
  for (int d = 0; d < Direction::kCount; ++d) {
    const Direction dir_d(d);
    Json e;
    e["direction"] = d;
    e["offset"] = dir_d.offset();
    const auto& t = by_direction[d];
    e["outcome"] = t ? transition_outcome_name(t->outcome) : "undecided";
    Json target = nullptr, level = nullptr, target_cp = nullptr;
    if (t && t->target.valid()) {
      const Configuration tc = cat.read_configuration(t->target);
      target = tc.id.value();
      level = tc.level.value();
      target_cp = tc.checkpoint.value();
    }
    e["target"] = target;
    e["target_level"] = level;
    e["target_checkpoint"] = target_cp;
    e["substeps"] = t ? Json(t->substeps) : Json(nullptr);
    e["newton_iterations"] = t ? Json(t->newton_iterations) : Json(nullptr);
    e["factorisations"] = t ? Json(t->factorisations) : Json(nullptr);
    e["final_residual"] = t ? Json(t->final_residual) : Json(nullptr);
    e["wall_ms"] = t ? Json(t->wall_ms) : Json(nullptr);
    e["failure_reason"] = t ? t->failure_reason : "";
    char line[256];
    const auto o = dir_d.offset();
    std::snprintf(
        line, sizeof line, "  %3d  (%2d,%2d,%2d)  %-12s  %6s  %5s  %8s  %5s  %7s  %-10s  %7s  %s\n",
        d, o[0], o[1], o[2], e["outcome"].get<std::string>().c_str(),
        target.is_null() ? "-" : target.dump().c_str(),
        level.is_null() ? "-" : level.dump().c_str(), t ? std::to_string(t->substeps).c_str() : "-",
        t ? std::to_string(t->newton_iterations).c_str() : "-",
        t ? std::to_string(t->factorisations).c_str() : "-",
        t ? num(t->final_residual).c_str() : "-", t ? num(t->wall_ms).c_str() : "-",
        t ? t->failure_reason.c_str() : "");
    s << line;
    list.push_back(e);
  }
  Json j = {{"config", id.value()},
            {"checkpoint", c.checkpoint.value()},
            {"level", c.level.value()},
            {"transitions", list}};
  return {dump(j), s.str()};
}

}  // namespace hapstate
