#include "statedir/scene_identity.h"

#include "scene/bind.h"
#include "statedir/stored_problem.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

namespace hapstate {
namespace {

const std::filesystem::path kBeam = HAPSTATE_SOURCE_DIR "/pipelines/beam/scene.toml";

std::string beam_text() {
  std::ifstream in(kBeam);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

NamedHashes identity_of(std::string text, const std::string& from = "",
                        const std::string& to = "") {
  if (!from.empty()) {
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
  }
  const Scene scene = parse_scene(text, kBeam);
  const Problem problem = build_problem(scene);
  return scene_identity(scene, problem, content_hash_file(scene.mesh.file));
}

std::vector<std::string> changed(const NamedHashes& a, const NamedHashes& b) {
  std::vector<std::string> names;
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].first, b[k].first);
    if (a[k].second != b[k].second) names.push_back(a[k].first);
  }
  return names;
}

TEST(SceneIdentity, PartsThatChange) {
  const NamedHashes base = identity_of(beam_text());
  ASSERT_EQ(base.size(), 10u);
  EXPECT_TRUE(std::is_sorted(base.begin(), base.end()));
  using V = std::vector<std::string>;
  EXPECT_EQ(changed(base, identity_of(beam_text())), V{});
  EXPECT_EQ(changed(base, identity_of(beam_text(), "# Small", "# A small")), V{"scene"});
  EXPECT_EQ(changed(base, identity_of(beam_text(), "max_force = 0.01", "max_force = 0.05")),
            (V{"max_force", "scene"}));
  EXPECT_EQ(changed(base, identity_of(beam_text(), "young = 5000.0", "young = 5000.5")),
            (V{"material", "scene"}));
  EXPECT_EQ(changed(base, identity_of(beam_text(), "substeps = 2", "substeps = 3")),
            (V{"scene", "solver"}));
  EXPECT_EQ(changed(base, identity_of(beam_text(), "spacing = 0.1", "spacing = 0.05")),
            (V{"grid.spacing", "scene"}));  // the box is explicit: the workspace stays
  EXPECT_EQ(
      changed(base, identity_of(beam_text(), "point = [4.0, 0.5, 1.0]", "point = [4.0, 0.5, 0.0]")),
      (V{"problem", "scene"}));
  EXPECT_TRUE(is_mutable_scene_part("max_force"));
  EXPECT_TRUE(is_mutable_scene_part("workspace"));
  EXPECT_FALSE(is_mutable_scene_part("material"));
  EXPECT_FALSE(is_mutable_scene_part("problem"));
}

}  // namespace
}  // namespace hapstate
