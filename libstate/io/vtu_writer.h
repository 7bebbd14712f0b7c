// Writes deformed meshes for ParaView: VTK XML UnstructuredGrid (.vtu, ASCII) files and a
// .pvd collection that orders them in time.
#pragma once

#include "mesh/mesh.h"

#include <Eigen/Core>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace hapstate {

// Writes `mesh` as drawn (the points are its node positions) with the point data
// "displacement" = u (3 x num_nodes, mesh units) as the active vectors: ParaView's Warp By
// Vector (scale 1) shows the deformed body, and the displacement is never counted twice.
void write_vtu(const std::filesystem::path& file, const Mesh& mesh, const Eigen::Matrix3Xd& u);

// Writes a ParaView collection listing (time, file) pairs; files relative to the .pvd.
void write_pvd(const std::filesystem::path& file,
               const std::vector<std::pair<double, std::string>>& steps);

}  // namespace hapstate
