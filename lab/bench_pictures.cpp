// SPDX-License-Identifier: MIT
#include "lab.h"
#include "bench_pictures.h"

#include <algorithm>
#include <iterator>

#include "image.h"
#include "methods.h"
#include "simdbvh/workloads/rays.h"

namespace simdbvh::lab {

namespace {

// Nodes visited per pixel, one ray at a time.
std::vector<std::uint32_t> visits(Tracer& t, std::span<const Ray> rays) {
    std::vector<std::uint32_t> c(rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i) {
        TraceStats s;
        Hit tmp;
        t.trace(rays.subspan(i, 1), std::span(&tmp, 1), false, &s);
        c[i] = std::uint32_t(s.nodes_visited);
    }
    return c;
}

}  // namespace

Pictures render_pictures(const Mesh& mesh, bool quick, int threads) {
    Pictures p;
    p.width = quick ? 320 : 640;
    p.height = quick ? 240 : 480;
    const int w = p.width, h = p.height;
    const auto rays = workloads::primary_rays(workloads::default_camera(mesh.bounds(), w, h));
    MethodSpec b8;
    b8.method = "bvh8";
    b8.isa = active_isa();
    b8.threads = threads;
    MethodSpec b2 = b8, em = b8;
    b2.method = "bvh2";
    em.method = "embree";
    auto t8 = make_tracer(mesh, b8);
    auto t2 = make_tracer(mesh, b2);
    auto te = make_tracer(mesh, em);
    std::vector<Hit> h8(rays.size()), h2(rays.size()), he(rays.size());
    t8->trace(rays, h8, false, nullptr);
    t2->trace(rays, h2, false, nullptr);
    te->trace(rays, he, false, nullptr);
    const std::vector<std::uint32_t> c2 = visits(*t2, rays), c8 = visits(*t8, rays);
    const std::uint32_t cmax = std::max<std::uint32_t>(1, *std::max_element(c2.begin(), c2.end()));
    const Image images[] = {shade_eye_light(mesh, rays, h8, w, h), heat_map(c2, w, h, cmax), heat_map(c8, w, h, cmax),
                            disagreement(h2, h8, w, h, &p.differ_bvh2_bvh8),
                            disagreement(h8, he, w, h, &p.differ_bvh8_embree)};
    static_assert(std::size(images) == std::size(kBenchPictures));
    for (std::size_t i = 0; i < std::size(images); ++i) p.png.emplace_back(kBenchPictures[i], encode_png(images[i]));
    return p;
}

}  // namespace simdbvh::lab
