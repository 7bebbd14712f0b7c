// Downstream use of an installed hapstate: the precise solver on a scene file through the
// public header only (argv[1]: the bundled beam's scene, a cantilever grabbed at its free end),
// then a bad scene file. Exits 0 only if the lift converged with the beam pulling the hand
// back down and the bad file was refused as hapstate::InputError naming it.
#include <hapstate/solver.h>

#include <cstdio>
#include <fstream>
#include <string>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: consumer SCENE.toml SCRATCH_DIR\n");
    return 2;
  }
  hapstate::SceneSolver solver(argv[1]);
  const hapstate::MoveOutcome m = solver.move_to(solver.probe_rest() + Eigen::Vector3d(0, 0, 0.2));
  if (!m.ok) {
    std::fprintf(stderr, "consumer: move failed: %s: %s\n", m.failure.c_str(), m.reason.c_str());
    return 1;
  }
  const Eigen::Vector3d f = solver.force_felt();
  std::printf("consumer: %d nodes, %d iterations, force felt = %.9g %.9g %.9g N\n",
              solver.num_nodes(), m.iterations, f.x(), f.y(), f.z());
  if (!f.allFinite() || f.z() >= 0) return 1;  // lifting the tip: the beam pulls it back down

  const std::string bad = std::string(argv[2]) + "/bad.toml";
  std::ofstream(bad) << "[mesh]\nfile = 7\n";
  try {
    hapstate::SceneSolver refused(bad);
    std::fprintf(stderr, "consumer: %s was accepted\n", bad.c_str());
    return 1;
  } catch (const hapstate::InputError& e) {
    if (std::string(e.what()).find("bad.toml") == std::string::npos) {
      std::fprintf(stderr, "consumer: the error does not name the file: %s\n", e.what());
      return 1;
    }
    std::printf("consumer: bad scene refused: %s\n", e.what());
  }
  return 0;
}
