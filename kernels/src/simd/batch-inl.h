#pragma once
// The batched loops of kernels/batch.h, written once for any 8-wide Arch and
// instantiated by src/avx2/kernels_avx2.cpp and src/avx512/kernels_avx512.cpp.
#include <algorithm>
#include <limits>

#include "simd/box8-inl.h"
#include "simd/prepare8-inl.h"
#include "simdbvh/kernels/batch.h"
#include "simd/dispatch.h"
#include "simd/tri8-inl.h"

namespace simdbvh::simd {

// The 8 x 8 bit matrix x (row k = byte k, column l = bit l) transposed: bit
// 8l + k of the result is bit 8k + l of x (Hacker's Delight 7-3).
SIMDBVH_FORCE_INLINE std::uint64_t transpose_bits8x8(std::uint64_t x) {
    std::uint64_t t = (x ^ (x >> 7)) & 0x00AA00AA00AA00AAull;
    x = x ^ t ^ (t << 7);
    t = (x ^ (x >> 14)) & 0x0000CCCC0000CCCCull;
    x = x ^ t ^ (t << 14);
    t = (x ^ (x >> 28)) & 0x00000000F0F0F0F0ull;
    return x ^ t ^ (t << 28);
}

template <class Arch>
struct BatchLoops {
    // batch.h's prepare_rays: prepare8() per 8 rays.
    static SIMDBVH_FORCE_INLINE void prepare_rays(std::span<const Ray> rays, const Aabb* bounds, PreparedRay* out,
                                                  std::uint8_t* ok) {
        for (std::size_t i = 0; i < rays.size(); i += 8) {
            const std::size_t g = std::min<std::size_t>(8, rays.size() - i);
            std::uint32_t valid;
            const std::uint32_t m = prepare8<Arch>(rays.data() + i, g, bounds, out + i, &valid);
            for (std::size_t l = 0; l < g; ++l) ok[i + l] = std::uint8_t(m >> l & 1u);
        }
    }
    static SIMDBVH_FORCE_INLINE void box8(std::span<const Ray> rays, const Box8& boxes, std::uint8_t* masks,
                                          float* entries) {
        for (std::size_t i = 0; i < rays.size(); ++i) {
            const PreparedRay r = prepare(rays[i]);
            if (!r.valid) {
                masks[i] = 0;
                for (int j = 0; j < 8; ++j) entries[8 * i + j] = std::numeric_limits<float>::infinity();
                continue;
            }
            const RayPack<Arch> p = pack_ray<Arch>(r);
            masks[i] = static_cast<std::uint8_t>(intersect_box8<Arch>(p, boxes, r.tmax, entries + 8 * i));
            if (r.t_exp != 0)
                for (int j = 0; j < 8; ++j) entries[8 * i + j] = to_caller_t(r, entries[8 * i + j]);
        }
    }

    // supers empty: every ray against every group; else against the supers,
    // then the groups in the super lanes it hits (the others: mask 0, +inf).
    static SIMDBVH_FORCE_INLINE void box8_groups(std::span<const Ray> rays, std::span<const Box8> supers,
                                                 std::span<const Box8> groups, std::uint8_t* masks,
                                                 float* entries) {
        const std::size_t ng = groups.size();
        const Batch<Arch> inf(std::numeric_limits<float>::infinity());
        for (std::size_t i = 0; i < rays.size(); ++i) {
            const PreparedRay r = prepare(rays[i]);
            float* e = entries + 8 * ng * i;
            std::uint8_t* m = masks + ng * i;
            if (!r.valid || !supers.empty()) {
                for (std::size_t g = 0; g < ng; ++g) {
                    m[g] = 0;
                    inf.store_unaligned(e + 8 * g);
                }
                if (!r.valid) continue;
            }
            const RayPack<Arch> p = pack_ray<Arch>(r);
            const Batch<Arch> tmax(r.tmax);
            auto group = [&](std::size_t g) __attribute__((always_inline)) {
                Batch<Arch> tn;
                m[g] = static_cast<std::uint8_t>(intersect_box8<Arch>(p, groups[g], tmax, tn));
                tn.store_unaligned(e + 8 * g);
            };
            if (supers.empty()) {
                for (std::size_t g = 0; g < ng; ++g) group(g);
            } else {
                for (std::size_t s = 0; s < supers.size(); ++s) {
                    Batch<Arch> tn;
                    for (std::uint32_t b = intersect_box8<Arch>(p, supers[s], tmax, tn); b != 0; b &= b - 1) {
                        const std::size_t g = 8 * s + std::size_t(__builtin_ctz(b));
                        if (g < ng) group(g);
                    }
                }
            }
            if (r.t_exp != 0)
                for (std::size_t j = 0; j < 8 * ng; ++j) e[j] = to_caller_t(r, e[j]);
        }
    }

    // batch.h's collect_box8_tree: the shared walk with this Arch's node test.
    struct TreeTest {
        const Box8* nodes;
        struct State {
            RayPack<Arch> p;
            float tmax;
        };
        SIMDBVH_FORCE_INLINE State ray(const PreparedRay& r) const { return {pack_ray<Arch>(r), r.tmax}; }
        SIMDBVH_FORCE_INLINE std::uint32_t mask(const State& s, std::uint32_t n, float* e) const {
            return intersect_box8<Arch>(s.p, nodes[n], s.tmax, e);
        }
    };
    static SIMDBVH_FORCE_INLINE kernels::detail::TreeWalk box8_tree(
        std::span<const Ray> rays, std::span<const std::uint8_t> live, std::span<const Box8> nodes,
        std::span<const std::uint32_t> children, std::size_t leaf_lanes, std::uint32_t* stack,
        std::pair<float, std::uint32_t>* out, std::size_t used, std::size_t cap, std::uint32_t* first) {
        return kernels::detail::walk_box_tree(rays, live, !nodes.empty(), children, leaf_lanes, stack, out, used, cap,
                                              first, TreeTest{nodes.data()});
    }

    // batch.h's collect_boxes: 8 rays per vector against one box at a time.
    // Each lane runs intersect_box's arithmetic on its own ray (its near
    // planes chosen by the signs of its reciprocals, as prepare() does), so
    // the bits are those of the per-ray tests. A ray whose direction
    // prepare() rescales (t_exp != 0) is tested alone against the groups.
    static SIMDBVH_FORCE_INLINE kernels::detail::TreeWalk boxes(std::span<const Ray> rays,
                                                                std::span<const std::uint8_t> live,
                                                                std::span<const Box8> groups, std::size_t count,
                                                                std::pair<float, std::uint32_t>* out,
                                                                std::size_t used, std::size_t cap,
                                                                std::uint32_t* first) {
        using B = Batch<Arch>;
        constexpr std::size_t kW = B::size;
        static_assert(kW == 8, "8 rays per batch");
        alignas(32) float ent[kernels::kCollectBoxesMax * kW];
        std::size_t i = 0;
        for (; i < rays.size(); i += kW) {
            const std::size_t g = std::min(kW, rays.size() - i);
            if (cap - used < g * count) break;
            std::uint32_t lanes = 0;
            for (std::size_t l = 0; l < g; ++l) lanes |= std::uint32_t(live.empty() || live[i + l] != 0) << l;
            if (lanes == 0) {  // no live ray (an any-hit query's rays that hit a plane, say)
                for (std::size_t l = 0; l < g; ++l) first[i + l] = std::uint32_t(used);
                continue;
            }
            // The rays' prepare() as far as the slab test needs it (prepare8-inl.h);
            // directions prepare() rescales go alone (below).
            const RayLanes8<Arch> r = ray_lanes8<Arch>(rays.data() + i, g);
            const std::uint32_t alone = r.alone & lanes;
            const std::uint32_t vec = r.valid & lanes & ~alone;
            // Box b's hit lanes are byte b % 8 of rows[b / 8]; transposed, byte l
            // of rows[q] holds lane l's hits among boxes 8q .. 8q + 7 (no branch
            // per hit: which rays hit which boxes is close to random).
            std::uint64_t rows[kernels::kCollectBoxesMax / kW] = {};
            if (vec != 0) {
                for (std::size_t b = 0; b < count; ++b) {
                    B tn;
                    const std::uint32_t h = box_lanes8<Arch>(r, groups[b / kW].get(int(b % kW)), tn);
                    tn.store_aligned(ent + kW * b);
                    rows[b / kW] |= std::uint64_t(h & vec) << (8 * (b % kW));
                }
            }
            const std::size_t nrows = (count + kW - 1) / kW;
            for (std::size_t q = 0; q < nrows; ++q) rows[q] = transpose_bits8x8(rows[q]);
            for (std::size_t l = 0; l < g; ++l) {
                first[i + l] = std::uint32_t(used);
                if ((alone >> l & 1u) == 0) {
                    for (std::size_t q0 = 0; q0 < nrows; q0 += 8) {  // 64 boxes per word
                        std::uint64_t hit = 0;  // lane l's ray hits box q0 * 8 + bit
                        for (std::size_t q = q0; q < std::min(nrows, q0 + 8); ++q)
                            hit |= ((rows[q] >> (8 * l)) & 0xFFu) << (8 * (q - q0));
                        for (std::uint64_t m = hit; m != 0; m &= m - 1) {
                            const std::size_t b = kW * q0 + std::size_t(__builtin_ctzll(m));
                            out[used++] = {ent[kW * b + l], std::uint32_t(b)};
                        }
                    }
                    continue;
                }
                const PreparedRay r = prepare(rays[i + l]);
                const RayPack<Arch> p = pack_ray<Arch>(r);
                for (std::size_t gi = 0; gi * kW < count; ++gi) {
                    alignas(32) float e[kW];
                    const std::size_t in_group = std::min(kW, count - gi * kW);
                    for (std::uint32_t m = intersect_box8<Arch>(p, groups[gi], r.tmax, e) & ((1u << in_group) - 1u);
                         m != 0; m &= m - 1) {
                        const int j = __builtin_ctz(m);
                        out[used++] = {to_caller_t(r, e[j]), std::uint32_t(gi * kW + std::size_t(j))};
                    }
                }
            }
        }
        return {std::min(i, rays.size()), used};
    }

    static SIMDBVH_FORCE_INLINE std::uint64_t count_box8(std::span<const Ray> rays, std::span<const Box8> blocks) {
        std::uint64_t n = 0;
        for (const Ray& ray : rays) {
            const PreparedRay r = prepare(ray);
            if (!r.valid) continue;
            const RayPack<Arch> p = pack_ray<Arch>(r);
            const Batch<Arch> tmax(r.tmax);
            for (const Box8& b : blocks) {
                Batch<Arch> tn;
                n += static_cast<std::uint64_t>(__builtin_popcount(intersect_box8<Arch>(p, b, tmax, tn)));
            }
        }
        return n;
    }

    // Brute force over every block, cache-blocked: a tile of kRayTile rays
    // walks the blocks kBlockTile at a time (about 20 KiB, in L1), so each
    // block is loaded once per tile instead of once per ray. Each ray still
    // sees the blocks in triangle order, so its answer is the untiled one.
    static constexpr std::size_t kRayTile = kernels::kBruteRayTile;
    static constexpr std::size_t kBlockTile = 64;

    struct Tile {
        PreparedRay r[kRayTile];
        RayPack<Arch> p[kRayTile];
        Hit best[kRayTile];
        bool live[kRayTile];
        std::size_t n = 0;
    };

    static SIMDBVH_FORCE_INLINE void load_tile(std::span<const Ray> rays, std::size_t i0, Tile& tile) {
        tile.n = std::min(kRayTile, rays.size() - i0);
        for (std::size_t k = 0; k < tile.n; ++k) {
            tile.r[k] = prepare(rays[i0 + k]);
            tile.best[k] = Hit{};
            tile.live[k] = tile.r[k].valid;
            if (tile.live[k]) {
                tile.p[k] = pack_ray<Arch>(tile.r[k]);
                tile.best[k].t = tile.r[k].tmax;
            }
        }
    }

    template <TriangleTest kTest>
    static SIMDBVH_FORCE_INLINE void closest(std::span<const Ray> rays, std::span<const Tri8> blocks, Hit* hits) {
        Tile tile;
        for (std::size_t i0 = 0; i0 < rays.size(); i0 += kRayTile) {
            load_tile(rays, i0, tile);
            for (std::size_t b0 = 0; b0 < blocks.size(); b0 += kBlockTile) {
                const std::span<const Tri8> chunk = blocks.subspan(b0, std::min(kBlockTile, blocks.size() - b0));
                for (std::size_t k = 0; k < tile.n; ++k) {
                    if (!tile.live[k]) continue;
                    const RayPack<Arch> p = tile.p[k];  // locals: kept in registers over the chunk
                    Hit best = tile.best[k];
                    for (const Tri8& b : chunk) intersect_tri8<Arch, kTest>(p, b, best);
                    tile.best[k] = best;
                }
            }
            for (std::size_t k = 0; k < tile.n; ++k) {
                Hit best = tile.best[k];
                if (!tile.live[k] || !best.hit()) best = Hit{};
                hits[i0 + k] = to_caller(tile.r[k], best);
            }
        }
    }

    template <TriangleTest kTest>
    static SIMDBVH_FORCE_INLINE void any(std::span<const Ray> rays, std::span<const Tri8> blocks,
                                         std::uint8_t* occluded, Hit* first_hits) {
        Tile tile;
        for (std::size_t i0 = 0; i0 < rays.size(); i0 += kRayTile) {
            load_tile(rays, i0, tile);
            bool found[kRayTile] = {};
            std::size_t open = 0;
            for (std::size_t k = 0; k < tile.n; ++k) open += tile.live[k] ? 1 : 0;
            for (std::size_t b0 = 0; b0 < blocks.size() && open != 0; b0 += kBlockTile) {
                const std::span<const Tri8> chunk = blocks.subspan(b0, std::min(kBlockTile, blocks.size() - b0));
                for (std::size_t k = 0; k < tile.n; ++k) {
                    if (!tile.live[k]) continue;
                    const RayPack<Arch> p = tile.p[k];
                    const float tmax = tile.r[k].tmax;
                    for (const Tri8& b : chunk)
                        if (occluded_tri8<Arch, kTest>(p, b, tmax, tile.best[k])) {
                            found[k] = true;
                            tile.live[k] = false;
                            --open;
                            break;
                        }
                }
            }
            for (std::size_t k = 0; k < tile.n; ++k) {
                occluded[i0 + k] = found[k] ? 1 : 0;
                if (first_hits) first_hits[i0 + k] = found[k] ? to_caller(tile.r[k], tile.best[k]) : Hit{};
            }
        }
    }
};

}  // namespace simdbvh::simd
