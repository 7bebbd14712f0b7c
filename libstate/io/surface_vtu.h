// Writes a triangulated surface for ParaView: a VTK XML UnstructuredGrid (.vtu, ASCII) of
// triangles, the playback viewer's frames (hapstate-play --frames).
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>

namespace hapstate {

// `positions`: 3 floats per vertex (the deformed surface); `triangles`: 3 vertex indices each.
// When `reference` is not empty (3 floats per vertex) the points written are the reference and
// the point data "displacement" = positions - reference are the active vectors (ParaView's Warp
// By Vector, scale 1, shows the deformed surface, never the displacement twice); without it the
// points are the positions. Throws InputError naming the file on a write error
// or when the arrays do not fit together.
void write_surface_vtu(const std::filesystem::path& file, std::span<const float> positions,
                       std::span<const std::int32_t> triangles,
                       std::span<const float> reference = {});

}  // namespace hapstate
