#include "mesh/load.h"
#include <gtest/gtest.h>
#include <chrono>
#include <iostream>
TEST(Tmp, Load) {
  for (std::string f : {std::string(HAPSTATE_TEST_DATA) + "/meshes/liver.msh", std::string(HAPSTATE_TEST_DATA) + "/meshes/bunny.msh", std::string("/work/shared/data/meshes/heart_tetra_200k.vtk")}) {
    hapstate::MeshReport r;
    auto t0 = std::chrono::steady_clock::now();
    auto m = hapstate::load_mesh(f, &r);
    double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::cout << f << " " << m.num_nodes() << " " << m.num_tets() << " " << m.surface.cols() << " groups " << m.groups.size() << " time " << s << "\n";
    for (auto& w : r.warnings) std::cout << "  " << w << "\n";
  }
}
