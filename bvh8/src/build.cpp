// Bvh8::build: collapse (collapse.cpp) then pack (pack.cpp).
#include <chrono>

#include "collapse.h"
#include "simdbvh/bvh8/bvh8.h"

namespace simdbvh {

std::string_view name(Collapse c) {
    switch (c) {
    case Collapse::sah: return "sah";
    case Collapse::greedy: return "greedy";
    }
    return "?";
}

std::optional<Collapse> parse_collapse(std::string_view s) {
    for (Collapse c : {Collapse::sah, Collapse::greedy})
        if (s == name(c)) return c;
    return std::nullopt;
}

struct Bvh8Access {
    static Bvh8 build(const Bvh2& bvh2, const Bvh8Options& opts) {
        const auto t0 = std::chrono::steady_clock::now();
        const bvh8::WideTopology topo = bvh8::collapse(bvh2, opts);
        Bvh8 b;
        bvh8::pack(bvh2, topo, b.nodes_, b.blocks_, b.stats_);
        b.stats_.sah_cost = bvh8::sah_cost(topo, opts);
        b.bounds_ = bvh2.bounds();
        b.stats_.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        return b;
    }
};

Bvh8 Bvh8::build(const Bvh2& bvh2, const Bvh8Options& opts) { return Bvh8Access::build(bvh2, opts); }

Bvh8 Bvh8::build(const Mesh& mesh, const BuildOptions& bvh2_opts, const Bvh8Options& opts) {
    return build(Bvh2::build(mesh, bvh2_opts), opts);
}

}  // namespace simdbvh
