// Binned SAH builder (Wald 2007, "On fast Construction of SAH-based Bounding
// Volume Hierarchies"), with SAH leaf-cost termination and a depth cap.
#include "build_common.h"

#include <algorithm>
#include <cmath>
#include <future>
#include <memory>
#include <vector>

namespace simdbvh::detail {

namespace {

struct Bin {
    Aabb box;
    std::uint32_t count = 0;
};

constexpr int kMaxBins = 256;

struct Split {
    int axis = -1;
    int bin = 0;  // primitives with bin index < bin go left
    float cost = 0;
};

struct Bins3 {
    Bin bins[3][kMaxBins];
};

// Bins ids[begin, end) on all three axes in one pass over the primitives.
void bin_range(const BuildContext& ctx, std::uint32_t begin, std::uint32_t end, int nbins, const float cmin[3],
               const float scale[3], Bins3& out) {
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < nbins; ++b) out.bins[a][b] = Bin{};
    for (std::uint32_t i = begin; i < end; ++i) {
        const std::uint32_t p = ctx.ids[i];
        const Vec3 c = ctx.centroids[p];
        const Aabb& box = ctx.boxes[p];
        for (int a = 0; a < 3; ++a) {
            if (scale[a] == 0.0f) continue;
            const int b = std::min(nbins - 1, int((c[a] - cmin[a]) * scale[a]));
            out.bins[a][b].box.grow(box);
            out.bins[a][b].count++;
        }
    }
}

// Ranges this large are binned by several threads; bins merge exactly
// (min/max and integer counts), so the result does not depend on the count.
constexpr std::uint32_t kParallelBinMin = 128 * 1024;

}  // namespace

SplitResult split_binned_sah(BuildContext& ctx, std::uint32_t begin, std::uint32_t end, const Aabb& node_box,
                             const Aabb& centroid_box, int /*depth*/) {
    const int nbins = std::clamp(ctx.opts.bins, 2, kMaxBins);
    const std::uint32_t n = end - begin;
    const float leaf_cost = ctx.opts.intersection_cost * float(n);
    const float parent_area = node_box.half_area();
    float cmin[3], scale[3];
    for (int a = 0; a < 3; ++a) {
        cmin[a] = centroid_box.lo[a];
        const float extent = centroid_box.hi[a] - cmin[a];
        scale[a] = extent > 0.0f ? float(nbins) / extent : 0.0f;
        if (!std::isfinite(scale[a])) scale[a] = 0.0f;
    }
    thread_local Bins3 tl_bins;  // one per thread: no allocation per node
    Bins3* bins = &tl_bins;
    const int workers = n >= kParallelBinMin ? std::min(ctx.opts.threads, 8) : 1;
    if (workers > 1) {
        std::vector<std::unique_ptr<Bins3>> parts(std::size_t(workers - 1));
        std::vector<std::future<void>> futs;
        const std::uint32_t chunk = (n + std::uint32_t(workers) - 1) / std::uint32_t(workers);
        for (int w = 1; w < workers; ++w) {
            parts[std::size_t(w - 1)] = std::make_unique<Bins3>();
            const std::uint32_t b = std::min(end, begin + chunk * std::uint32_t(w));
            const std::uint32_t e = std::min(end, b + chunk);
            Bins3* out = parts[std::size_t(w - 1)].get();
            futs.push_back(std::async(std::launch::async, [&, b, e, out] { bin_range(ctx, b, e, nbins, cmin, scale, *out); }));
        }
        bin_range(ctx, begin, std::min(end, begin + chunk), nbins, cmin, scale, *bins);
        for (auto& f : futs) f.get();
        for (const auto& part : parts)
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < nbins; ++b) {
                    bins->bins[a][b].box.grow(part->bins[a][b].box);
                    bins->bins[a][b].count += part->bins[a][b].count;
                }
    } else {
        bin_range(ctx, begin, end, nbins, cmin, scale, *bins);
    }
    Split best;
    best.cost = std::numeric_limits<float>::infinity();
    float right_area[kMaxBins];
    std::uint32_t right_count[kMaxBins];
    for (int axis = 0; axis < 3; ++axis) {
        if (scale[axis] == 0.0f) continue;
        const Bin* bn = bins->bins[axis];
        Aabb acc;
        std::uint32_t cnt = 0;
        for (int b = nbins - 1; b > 0; --b) {
            acc.grow(bn[b].box);
            cnt += bn[b].count;
            right_area[b] = acc.half_area();
            right_count[b] = cnt;
        }
        acc = Aabb{};
        cnt = 0;
        for (int b = 1; b < nbins; ++b) {
            acc.grow(bn[b - 1].box);
            cnt += bn[b - 1].count;
            if (cnt == 0 || right_count[b] == 0) continue;
            const float cost = ctx.opts.traversal_cost +
                               ctx.opts.intersection_cost *
                                   (acc.half_area() * float(cnt) + right_area[b] * float(right_count[b])) / parent_area;
            if (cost < best.cost) best = {axis, b, cost};
        }
    }
    SplitResult r;
    if (best.axis < 0) return r;  // no usable split: caller falls back
    r.make_leaf = best.cost >= leaf_cost && n <= std::uint32_t(ctx.opts.max_leaf_size);
    if (r.make_leaf) return r;
    const int axis = best.axis;
    std::uint32_t* first = ctx.ids.data() + begin;
    std::uint32_t* mid = std::partition(first, ctx.ids.data() + end, [&](std::uint32_t p) {
        return std::min(nbins - 1, int((ctx.centroids[p][axis] - cmin[axis]) * scale[axis])) < best.bin;
    });
    r.mid = begin + std::uint32_t(mid - first);
    r.found = true;
    return r;
}

}  // namespace simdbvh::detail
