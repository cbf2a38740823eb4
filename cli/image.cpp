#include "image.h"

#include <stb_image_write.h>

#include <algorithm>
#include <cmath>

#include "simdbvh/kernels/error.h"
#include "simdbvh/workloads/rays.h"
#include "simdbvh/io/output.h"

namespace simdbvh::cli {

Image shade_eye_light(const Mesh& mesh, std::span<const Ray> rays, std::span<const Hit> hits, int w, int h) {
    Image img{w, h, std::vector<std::uint8_t>(std::size_t(w) * std::size_t(h) * 3, 0)};
    for (std::size_t i = 0; i < std::size_t(w) * std::size_t(h) && i < hits.size(); ++i) {
        if (!hits[i].hit()) continue;
        const Vec3 a = mesh.vertex(hits[i].prim, 0), b = mesh.vertex(hits[i].prim, 1), c = mesh.vertex(hits[i].prim, 2);
        const Vec3 n = cross(b - a, c - a);
        const float ln = length(n), ld = length(rays[i].dir);
        const float s = ln > 0 && ld > 0 ? std::fabs(dot(n, rays[i].dir)) / (ln * ld) : 0.0f;
        const auto g = std::uint8_t(std::clamp(40.0f + 215.0f * s, 0.0f, 255.0f));
        img.rgb[3 * i + 0] = g;
        img.rgb[3 * i + 1] = g;
        img.rgb[3 * i + 2] = std::uint8_t(std::min(255, int(g) + 10));
    }
    return img;
}

Image heat_map(std::span<const std::uint32_t> counts, int w, int h, std::uint32_t max_count) {
    Image img{w, h, std::vector<std::uint8_t>(std::size_t(w) * std::size_t(h) * 3, 0)};
    if (max_count == 0)
        for (std::uint32_t c : counts) max_count = std::max(max_count, c);
    max_count = std::max<std::uint32_t>(max_count, 1);
    for (std::size_t i = 0; i < counts.size() && i < std::size_t(w) * std::size_t(h); ++i) {
        const float x = std::min(1.0f, float(counts[i]) / float(max_count));
        // blue -> green -> yellow -> red
        const float r = std::clamp(2.0f * x - 0.5f, 0.0f, 1.0f);
        const float g = std::clamp(x < 0.75f ? 2.0f * x : 4.0f * (1.0f - x), 0.0f, 1.0f);
        const float b = std::clamp(1.0f - 2.5f * x, 0.0f, 1.0f) * (x > 0 ? 1.0f : 0.0f);
        img.rgb[3 * i + 0] = std::uint8_t(255 * r);
        img.rgb[3 * i + 1] = std::uint8_t(255 * g);
        img.rgb[3 * i + 2] = std::uint8_t(255 * b);
    }
    return img;
}

Image disagreement(std::span<const Hit> a, std::span<const Hit> b, int w, int h, std::size_t* differing) {
    Image img{w, h, std::vector<std::uint8_t>(std::size_t(w) * std::size_t(h) * 3, 0)};
    std::size_t n = 0;
    for (std::size_t i = 0; i < a.size() && i < b.size() && i < std::size_t(w) * std::size_t(h); ++i) {
        if (a[i].prim == b[i].prim) continue;
        ++n;
        img.rgb[3 * i] = 255;
    }
    if (differing) *differing = n;
    return img;
}

std::vector<unsigned char> encode_png(const Image& img) {
    std::vector<unsigned char> bytes;
    auto sink = [](void* ctx, void* data, int size) {
        auto* v = static_cast<std::vector<unsigned char>*>(ctx);
        v->insert(v->end(), static_cast<unsigned char*>(data), static_cast<unsigned char*>(data) + size);
    };
    if (!stbi_write_png_to_func(sink, &bytes, img.width, img.height, 3, img.rgb.data(), img.width * 3))
        throw Error("PNG encoding failed (" + std::to_string(img.width) + "x" + std::to_string(img.height) + ")");
    return bytes;
}

void write_png(const std::string& file, const Image& img) {
    std::vector<unsigned char> bytes;
    try {
        bytes = encode_png(img);
    } catch (const Error& e) {
        throw Error(file + ": " + e.what());
    }
    io::write_file_atomic(file, bytes);
}

}  // namespace simdbvh::cli
