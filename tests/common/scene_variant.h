// Copies of the bundled scenes for tests: the text of a scene with edits, its mesh named by its
// absolute path, written into the test's folder.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace hapstate::test_util {

inline const std::string kBeamScene = HAPSTATE_SOURCE_DIR "/pipelines/beam/scene.toml";
inline const std::string kPlateScene = HAPSTATE_SOURCE_DIR "/pipelines/plate/scene.toml";

inline std::string slurp(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// A copy of `scene` in `dir` named `name`, with each (from, to) text replacement applied (each
// `from` must occur) and its mesh file `mesh` (beside the scene) named by its absolute path.
inline std::string scene_variant(const std::string& scene, const std::string& mesh,
                                 const std::filesystem::path& dir, const std::string& name,
                                 const std::vector<std::pair<std::string, std::string>>& edits) {
  std::string text = slurp(scene);
  std::vector<std::pair<std::string, std::string>> all = edits;
  all.emplace_back(
      "file = \"" + mesh + "\"",
      "file = \"" + (std::filesystem::path(scene).parent_path() / mesh).string() + "\"");
  for (const auto& [from, to] : all) {
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
  }
  const std::filesystem::path file = dir / name;
  std::ofstream(file) << text;
  return file.string();
}

inline std::string beam_variant(const std::filesystem::path& dir, const std::string& name,
                                const std::vector<std::pair<std::string, std::string>>& edits) {
  return scene_variant(kBeamScene, "beam.msh", dir, name, edits);
}

// The bundled plate scene on the tests' coarse plate mesh (plate_coarse.msh: 0.4 cm cells, a
// quarter of the bundled mesh's nodes), with `edits`, as `dir`/plate.toml.
inline std::string plate_variant(const std::filesystem::path& dir,
                                 const std::vector<std::pair<std::string, std::string>>& edits) {
  std::vector<std::pair<std::string, std::string>> all{
      {"file = \"plate.msh\"", "file = \"plate_coarse.msh\""}};
  all.insert(all.end(), edits.begin(), edits.end());
  return scene_variant(kPlateScene, "plate_coarse.msh", dir, "plate.toml", all);
}

}  // namespace hapstate::test_util
