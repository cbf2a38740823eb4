#pragma once
// Strict, exact mesh loaders: PLY (ASCII, binary LE/BE), OBJ, STL (ASCII,
// binary), OFF, each optionally gzip-compressed. Faces keep file order;
// polygons are fan-triangulated in order; vertices are never merged. Numbers
// are parsed with std::from_chars (correctly rounded). Errors throw
// simdbvh::Error with the file name (and line where known).
#include <filesystem>
#include <string_view>

#include "simdbvh/kernels/mesh.h"

namespace simdbvh::io {

struct LoadOptions {
    bool drop_invalid = false;  // opt-in: drop triangles with non-finite vertices and count them
};
struct LoadReport {
    std::size_t dropped_triangles = 0;
};

Mesh load_mesh(const std::filesystem::path& file, const LoadOptions& opts = {}, LoadReport* report = nullptr);

}  // namespace simdbvh::io
