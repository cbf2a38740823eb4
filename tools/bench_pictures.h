// SPDX-License-Identifier: MIT
#pragma once
// The bench report's pictures: a BVH8 render, node heat maps for BVH2 and
// BVH8, disagreement masks BVH2 vs BVH8 and BVH8 vs Embree.
#include <filesystem>

#include "simdbvh/mesh.h"

namespace simdbvh::cli {

struct Pictures {
    int width = 0, height = 0;
    std::size_t differ_bvh2_bvh8 = 0, differ_bvh8_embree = 0;  // pixels
};

// Writes render_bvh8.png, heat_bvh2.png, heat_bvh8.png, disagree_bvh2_bvh8.png, disagree_bvh8_embree.png.
Pictures write_pictures(const Mesh& mesh, const std::filesystem::path& dir, bool quick, int threads);

}  // namespace simdbvh::cli
