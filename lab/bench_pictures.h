// SPDX-License-Identifier: MIT
#pragma once
// The bench report's pictures: a BVH8 render, node heat maps for BVH2 and
// BVH8, disagreement masks BVH2 vs BVH8 and BVH8 vs Embree.
#include <string>
#include <utility>
#include <vector>

#include "lab.h"
#include "simdbvh/kernels/mesh.h"

namespace simdbvh::lab {

// The file names, in the report folder.
inline constexpr const char* kBenchPictures[] = {"render_bvh8.png", "heat_bvh2.png", "heat_bvh8.png",
                                                 "disagree_bvh2_bvh8.png", "disagree_bvh8_embree.png"};

struct Pictures {
    int width = 0, height = 0;
    std::size_t differ_bvh2_bvh8 = 0, differ_bvh8_embree = 0;             // pixels
    std::vector<std::pair<std::string, std::vector<unsigned char>>> png;  // (file name, PNG bytes), as above
};

// The pictures, encoded (written with the rest of the report).
Pictures render_pictures(const Mesh& mesh, bool quick, int threads);

}  // namespace simdbvh::lab
