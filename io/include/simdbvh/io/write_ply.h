#pragma once
// Writing a mesh: the ray families' files and the cached procedural scenes.
#include <filesystem>
#include <vector>

#include "simdbvh/kernels/mesh.h"

namespace simdbvh::io {

// Binary little-endian PLY (float x y z, uchar/uint faces), written atomically; encode_ply: its bytes.
std::vector<unsigned char> encode_ply(const Mesh& mesh);
void write_ply(const std::filesystem::path& file, const Mesh& mesh);

}  // namespace simdbvh::io
