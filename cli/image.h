#pragma once
// Pictures for the bench report: eye-light shading, node heat maps and
// disagreement masks, written as PNG (stb) through a temp file + rename.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "simdbvh/kernels/hit.h"
#include "simdbvh/kernels/ray.h"
#include "simdbvh/kernels/mesh.h"
#include "simdbvh/io/output.h"

namespace simdbvh::cli {

struct Image {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgb;  // 3 bytes per pixel, row-major from the top-left
};

// Shade = |cos| between the ray and the geometric normal (eye light); misses black.
Image shade_eye_light(const Mesh& mesh, std::span<const Ray> rays, std::span<const Hit> hits, int w, int h);
// Heat map of per-pixel counts (e.g. nodes visited), on a fixed colour ramp scaled to `max_count`
// (0: the image's own maximum).
Image heat_map(std::span<const std::uint32_t> counts, int w, int h, std::uint32_t max_count = 0);
// Red where the two hit arrays differ (different triangle or hit/miss), black elsewhere.
Image disagreement(std::span<const Hit> a, std::span<const Hit> b, int w, int h, std::size_t* differing = nullptr);
// The PNG file's bytes (stb); write_png writes them through io::write_file_atomic.
std::vector<unsigned char> encode_png(const Image& img);
void write_png(const std::string& file, const Image& img);

}  // namespace simdbvh::cli
