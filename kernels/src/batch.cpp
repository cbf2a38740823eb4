// The public batched entry points: validate the spans, then pick the ISA's
// kernel set (with_kernels, simd/dispatch.h); its translation unit does the work.
#include "simdbvh/kernels/batch.h"
#include "simdbvh/kernels/testing.h"

#include <algorithm>
#include <string>
#include <vector>

#include "simd/dispatch.h"
#include "simdbvh/kernels/error.h"

namespace simdbvh::kernels {

namespace {
thread_local int t_last_isa = -1;
using simdbvh::detail::check_size;
}  // namespace

namespace detail {
void note_isa_used(Isa isa) { t_last_isa = static_cast<int>(isa); }
}  // namespace detail

std::optional<Isa> last_isa_used() {
    if (t_last_isa < 0) return std::nullopt;
    return static_cast<Isa>(t_last_isa);
}

Isa compiled_isa(Isa isa) {
    return with_kernels(isa, [&]<class K>() { return K::compiled_isa(); });
}

void intersect_box8(std::span<const Ray> rays, const Box8& boxes, std::span<std::uint8_t> masks,
                    std::span<float> entries, Isa isa) {
    require(isa);
    check_size(masks.size(), rays.size(), "masks");
    check_size(entries.size(), 8 * rays.size(), "entries");
    return with_kernels(isa, [&]<class K>() { return K::intersect_box8(rays, boxes, masks.data(), entries.data()); });
}

void intersect_box8_groups(std::span<const Ray> rays, std::span<const Box8> groups, std::span<std::uint8_t> masks,
                           std::span<float> entries, Isa isa) {
    require(isa);
    check_size(masks.size(), groups.size() * rays.size(), "masks");
    check_size(entries.size(), 8 * groups.size() * rays.size(), "entries");
    return with_kernels(
        isa, [&]<class K>() { return K::intersect_box8_groups(rays, {}, groups, masks.data(), entries.data()); });
}

void intersect_box8_nested(std::span<const Ray> rays, std::span<const Box8> supers, std::span<const Box8> groups,
                           std::span<std::uint8_t> masks, std::span<float> entries, Isa isa) {
    require(isa);
    if (groups.size() > 8 * supers.size())
        throw Error("" + std::to_string(groups.size()) + " groups need " + std::to_string((groups.size() + 7) / 8) +
                    " supers, got " + std::to_string(supers.size()));
    check_size(masks.size(), groups.size() * rays.size(), "masks");
    check_size(entries.size(), 8 * groups.size() * rays.size(), "entries");
    if (supers.empty()) return;  // no groups
    return with_kernels(
        isa, [&]<class K>() { return K::intersect_box8_groups(rays, supers, groups, masks.data(), entries.data()); });
}

void collect_box8_tree(std::span<const Ray> rays, std::span<const std::uint8_t> live, std::span<const Box8> nodes,
                       std::span<const std::uint32_t> children, std::vector<std::pair<float, std::uint32_t>>& out,
                       std::span<std::uint32_t> first, Isa isa) {
    require(isa);
    check_size(children.size(), 8 * nodes.size(), "children");
    check_size(first.size(), rays.size() + 1, "first");
    if (!live.empty()) check_size(live.size(), rays.size(), "live");
    // A tree: inner children after their parent, each reached from one lane
    // (so every walk ends and its stack holds at most nodes.size() entries).
    std::vector<std::uint8_t> reached(nodes.size(), 0);
    for (std::size_t k = 0; k < children.size(); ++k) {
        const std::uint32_t c = children[k];
        if (c == kBoxTreeEmpty || (c & kBoxTreeLeaf) != 0) continue;
        if (c <= k / 8 || c >= nodes.size() || reached[c]++ != 0)
            throw Error("box tree: lane " + std::to_string(k % 8) + " of node " + std::to_string(k / 8) +
                        " names node " + std::to_string(c) + ", which is not a later node reached once");
    }
    // Each ray reaches at most every leaf lane once: the walk stops before a
    // ray that might not fit, and the output grows (by half) for the rest.
    std::size_t leaf_lanes = 0;
    for (const std::uint32_t c : children) leaf_lanes += c != kBoxTreeEmpty && (c & kBoxTreeLeaf) != 0;
    std::vector<std::uint32_t> stack(std::max<std::size_t>(nodes.size(), 1));
    const auto walk = with_kernels(isa, [&]<class K>() { return &K::collect_box8_tree; });
    std::size_t used = out.size(), done = 0;
    constexpr std::size_t kMaxOut = 0xFFFFFFFFu;  // first[] holds 32-bit offsets
    for (;;) {
        const std::size_t cap = std::max(used + leaf_lanes, used + used / 2 + 1024);
        if (cap > kMaxOut) throw Error("box tree: more than 2^32 - 1 results");
        out.resize(cap);
        const std::span<const Ray> rest = rays.subspan(done);
        const std::span<const std::uint8_t> rest_live = live.empty() ? live : live.subspan(done);
        const detail::TreeWalk w = walk(rest, rest_live, nodes, children, leaf_lanes, stack.data(), out.data(), used,
                                        cap, first.data() + done);
        used = w.used;
        done += w.rays_done;
        if (done == rays.size()) break;
    }
    out.resize(used);
    first[rays.size()] = std::uint32_t(used);
}

void collect_boxes(std::span<const Ray> rays, std::span<const std::uint8_t> live, std::span<const Aabb> boxes,
                   std::vector<std::pair<float, std::uint32_t>>& out, std::span<std::uint32_t> first, Isa isa) {
    require(isa);
    check_size(first.size(), rays.size() + 1, "first");
    if (!live.empty()) check_size(live.size(), rays.size(), "live");
    if (boxes.size() > kCollectBoxesMax)
        throw Error("collect_boxes: " + std::to_string(boxes.size()) + " boxes, at most " +
                    std::to_string(kCollectBoxesMax));
    std::vector<Box8> groups((boxes.size() + 7) / 8);
    for (Box8& g : groups) g.clear();
    for (std::size_t b = 0; b < boxes.size(); ++b) groups[b / 8].set(int(b % 8), boxes[b]);
    const auto walk = with_kernels(isa, [&]<class K>() { return &K::collect_boxes; });
    // As collect_box8_tree: the output grows (by half) until every ray fits;
    // a call needs room for 8 rays' worst case to make progress.
    std::size_t used = out.size(), done = 0;
    constexpr std::size_t kMaxOut = 0xFFFFFFFFu;
    for (;;) {
        const std::size_t cap = std::max(used + 8 * boxes.size(), used + used / 2 + 1024);
        if (cap > kMaxOut) throw Error("collect_boxes: more than 2^32 - 1 results");
        out.resize(cap);
        const std::span<const Ray> rest = rays.subspan(done);
        const std::span<const std::uint8_t> rest_live = live.empty() ? live : live.subspan(done);
        const detail::TreeWalk w =
            walk(rest, rest_live, groups, boxes.size(), out.data(), used, cap, first.data() + done);
        used = w.used;
        done += w.rays_done;
        if (done == rays.size()) break;
    }
    out.resize(used);
    first[rays.size()] = std::uint32_t(used);
}

void prepare_rays(std::span<const Ray> rays, const Aabb* bounds, std::span<PreparedRay> out, std::span<std::uint8_t> ok,
                  Isa isa) {
    require(isa);
    check_size(out.size(), rays.size(), "out");
    check_size(ok.size(), rays.size(), "ok");
    const auto run = with_kernels(isa, [&]<class K>() { return &K::prepare_rays; });
    run(rays, bounds, out.data(), ok.data());
}

std::uint64_t count_box8_hits(std::span<const Ray> rays, std::span<const Box8> blocks, Isa isa) {
    return with_kernels(isa, [&]<class K>() { return K::count_box8_hits(rays, blocks); });
}

void intersect_tri8(std::span<const Ray> rays, std::span<const Tri8> blocks, TriangleTest test, std::span<Hit> hits,
                    Isa isa) {
    require(isa);
    check_size(hits.size(), rays.size(), "hits");
    return with_kernels(isa, [&]<class K>() { return K::intersect_tri8(rays, blocks, test, hits.data()); });
}

void occluded_tri8(std::span<const Ray> rays, std::span<const Tri8> blocks, TriangleTest test,
                   std::span<std::uint8_t> occluded, std::span<Hit> first_hits, Isa isa) {
    require(isa);
    check_size(occluded.size(), rays.size(), "occluded");
    if (!first_hits.empty()) check_size(first_hits.size(), rays.size(), "first_hits");
    Hit* fh = first_hits.empty() ? nullptr : first_hits.data();
    return with_kernels(isa, [&]<class K>() { return K::occluded_tri8(rays, blocks, test, occluded.data(), fh); });
}

}  // namespace simdbvh::kernels
