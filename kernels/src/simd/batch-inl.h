#pragma once
// The batched loops of kernels/batch.h, written once for any 8-wide Arch and
// instantiated by src/avx2/kernels_avx2.cpp and src/avx512/kernels_avx512.cpp.
#include <algorithm>
#include <limits>

#include "simdbvh/kernels/internal/simd/box8-inl.h"
#include "simdbvh/kernels/internal/simd/prepare8-inl.h"
#include "simdbvh/kernels/batch.h"
#include "simd/dispatch.h"
#include "simdbvh/kernels/internal/simd/tri8-inl.h"

namespace simdbvh::kernels::simd {

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
                                                 std::span<const Box8> groups, std::uint8_t* masks, float* entries) {
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

    // The loop both collect_boxes forms share: 8 rays at a time, prepared as
    // far as the slab test needs in vector lanes (ray_lanes8, prepare8-inl.h).
    // `test(r, vec)` gives the appender of the valid live lanes `vec`
    // (lane(l, used) appends lane l's boxes and entries from out[used], returns
    // the new end); a ray whose direction prepare() rescales (t_exp != 0) goes
    // through prepare() against every group; other lanes report nothing.
    template <class Test>
    static SIMDBVH_FORCE_INLINE kernels::detail::TreeWalk each_ray8(std::span<const Ray> rays,
                                                                    std::span<const std::uint8_t> live,
                                                                    std::span<const Box8> groups, std::size_t count,
                                                                    std::pair<float, std::uint32_t>* out,
                                                                    std::size_t used, std::size_t cap,
                                                                    std::uint32_t* first, const Test& test) {
        constexpr std::size_t kW = 8;
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
            const RayLanes8<Arch> r = ray_lanes8<Arch>(rays.data() + i, g);
            const std::uint32_t alone = r.alone & lanes;
            const std::uint32_t vec = r.valid & lanes & ~alone;
            const auto lane = test(r, vec);
            for (std::size_t l = 0; l < g; ++l) {
                first[i + l] = std::uint32_t(used);
                if ((vec >> l & 1u) != 0) {
                    used = lane(l, used);
                    continue;
                }
                if ((alone >> l & 1u) == 0) continue;
                const PreparedRay pr = prepare(rays[i + l]);
                const RayPack<Arch> p = pack_ray<Arch>(pr);
                for (std::size_t gi = 0; gi * kW < count; ++gi) {
                    alignas(32) float e[kW];
                    const std::size_t in_group = std::min(kW, count - gi * kW);
                    for (std::uint32_t m = intersect_box8<Arch>(p, groups[gi], pr.tmax, e) & ((1u << in_group) - 1u);
                         m != 0; m &= m - 1) {
                        const int j = __builtin_ctz(m);
                        out[used++] = {to_caller_t(pr, e[j]), std::uint32_t(gi * kW + std::size_t(j))};
                    }
                }
            }
        }
        return {std::min(i, rays.size()), used};
    }

    // collect_boxes in lanes: 8 rays per vector against one box at a time.
    // Each lane runs intersect_box's arithmetic on its own ray (its near
    // planes chosen by the signs of its reciprocals, as prepare() does), so
    // the bits are those of the per-ray tests.
    static SIMDBVH_FORCE_INLINE kernels::detail::TreeWalk boxes_in_lanes(
        std::span<const Ray> rays, std::span<const std::uint8_t> live, std::span<const Box8> groups, std::size_t count,
        std::pair<float, std::uint32_t>* out, std::size_t used, std::size_t cap, std::uint32_t* first) {
        using B = Batch<Arch>;
        constexpr std::size_t kW = B::size;
        static_assert(kW == 8, "8 rays per batch");
        alignas(32) float ent[kernels::kCollectBoxesMax * kW];
        // Box b's hit lanes are byte b % 8 of rows[b / 8]; transposed, byte l
        // of rows[q] holds lane l's hits among boxes 8q .. 8q + 7 (no branch
        // per hit: which rays hit which boxes is close to random).
        std::uint64_t rows[kernels::kCollectBoxesMax / kW];
        const std::size_t nrows = (count + kW - 1) / kW;
        const auto test = [&](const RayLanes8<Arch>& r, std::uint32_t vec) __attribute__((always_inline)) {
            for (std::size_t q = 0; q < nrows; ++q) rows[q] = 0;
            if (vec != 0) {
                for (std::size_t b = 0; b < count; ++b) {
                    B tn;
                    const std::uint32_t h = box_lanes8<Arch>(r, groups[b / kW].get(int(b % kW)), tn);
                    tn.store_aligned(ent + kW * b);
                    rows[b / kW] |= std::uint64_t(h & vec) << (8 * (b % kW));
                }
            }
            for (std::size_t q = 0; q < nrows; ++q) rows[q] = transpose_bits8x8(rows[q]);
            return [&](std::size_t l, std::size_t used) __attribute__((always_inline)) {
                for (std::size_t q0 = 0; q0 < nrows; q0 += 8) {  // 64 boxes per word
                    std::uint64_t hit = 0;                       // lane l's ray hits box q0 * 8 + bit
                    for (std::size_t q = q0; q < std::min(nrows, q0 + 8); ++q)
                        hit |= ((rows[q] >> (8 * l)) & 0xFFu) << (8 * (q - q0));
                    for (std::uint64_t m = hit; m != 0; m &= m - 1) {
                        const std::size_t b = kW * q0 + std::size_t(__builtin_ctzll(m));
                        out[used++] = {ent[kW * b + l], std::uint32_t(b)};
                    }
                }
                return used;
            };
        };
        return each_ray8(rays, live, groups, count, out, used, cap, first, test);
    }

    // collect_boxes under unions: each ray alone against the groups of 8
    // boxes under a first level of super boxes (lane j of super s: the union
    // of group 8s + j's boxes), testing only the groups whose super lane it
    // hits. The conservative test is monotone in the box (a box inside one the
    // test misses is missed: rounding is monotone, and a NaN slab value, an
    // origin on a plane of a zero direction component, is discarded as the
    // most permissive value), so no hit box is skipped; a box with a NaN
    // coordinate makes its super lane unbounded. Each hit's entry is
    // intersect_box8's lane, intersect_box's bits. A ray of instances-100's
    // incoherent chunks tests the 2 supers and 3.46 of the 13 groups (0.52 of
    // them with a hit).
    static SIMDBVH_FORCE_INLINE kernels::detail::TreeWalk boxes_under_unions(
        std::span<const Ray> rays, std::span<const std::uint8_t> live, std::span<const Box8> groups, std::size_t count,
        std::pair<float, std::uint32_t>* out, std::size_t used, std::size_t cap, std::uint32_t* first) {
        using B = Batch<Arch>;
        constexpr std::size_t kW = B::size;
        static_assert(kW == 8, "8 rays per batch");
        constexpr float kInf = std::numeric_limits<float>::infinity();
        Box8 supers[kernels::kCollectBoxesMax / 64];
        const std::size_t nsup = (groups.size() + kW - 1) / kW;
        for (std::size_t q = 0; q < nsup; ++q) {
            supers[q].clear();
            for (std::size_t j = 0; j < kW && kW * q + j < groups.size(); ++j) {
                const std::size_t g = kW * q + j;
                Aabb u;
                bool nan = false;
                for (std::size_t k = 0; k < kW && kW * g + k < count; ++k) {
                    const Aabb b = groups[g].get(int(k));
                    nan |= !(b.lo.x == b.lo.x && b.lo.y == b.lo.y && b.lo.z == b.lo.z && b.hi.x == b.hi.x &&
                             b.hi.y == b.hi.y && b.hi.z == b.hi.z);
                    u.grow(b);
                }
                supers[q].set(int(j), nan ? Aabb{{-kInf, -kInf, -kInf}, {kInf, kInf, kInf}} : u);
            }
        }
        alignas(32) float f[9][kW];
        std::uint32_t hx = 0, hy = 0, hz = 0;
        const auto test = [&](const RayLanes8<Arch>& r, std::uint32_t vec) __attribute__((always_inline)) {
            if (vec != 0) {
                r.ox.store_aligned(f[0]);
                r.oy.store_aligned(f[1]);
                r.oz.store_aligned(f[2]);
                r.rdx.store_aligned(f[3]);
                r.rdy.store_aligned(f[4]);
                r.rdz.store_aligned(f[5]);
                r.tmin.store_aligned(f[6]);
                r.tmax.store_aligned(f[7]);
                r.slack.store_aligned(f[8]);
                hx = bits<Arch>(r.hx), hy = bits<Arch>(r.hy), hz = bits<Arch>(r.hz);
            }
            return [&](std::size_t l, std::size_t used) __attribute__((always_inline)) {
                // The lane's RayPack, as pack_ray() of its PreparedRay (the slab test's fields).
                RayPack<Arch> p;
                p.ox = f[0][l], p.oy = f[1][l], p.oz = f[2][l];
                p.rdx = f[3][l], p.rdy = f[4][l], p.rdz = f[5][l];
                p.tmin = f[6][l], p.far_slack = f[8][l];
                const std::uint32_t nx = hx >> l & 1u, ny = hy >> l & 1u, nz = hz >> l & 1u;
                p.near_x = 32u * nx, p.far_x = 32u * (1u - nx);
                p.near_y = 64u + 32u * ny, p.far_y = 64u + 32u * (1u - ny);
                p.near_z = 128u + 32u * nz, p.far_z = 128u + 32u * (1u - nz);
                const B tmax(f[7][l]);
                std::uint32_t reach = 0;  // bit g: the ray hits group g's super lane
                for (std::size_t q = 0; q < nsup; ++q) {
                    B ts;
                    reach |= intersect_box8<Arch>(p, supers[q], tmax, ts) << (kW * q);
                }
                for (; reach != 0; reach &= reach - 1) {
                    const std::size_t gi = std::size_t(__builtin_ctz(reach));  // < groups.size()
                    B tn;
                    alignas(32) float e[kW];
                    const std::uint32_t h = intersect_box8<Arch>(p, groups[gi], tmax, tn);
                    tn.store_aligned(e);
                    for (std::uint32_t k = h; k != 0; k &= k - 1) {
                        const int j = __builtin_ctz(k);
                        out[used++] = {e[j], std::uint32_t(kW * gi + std::size_t(j))};
                    }
                }
                return used;
            };
        };
        return each_ray8(rays, live, groups, count, out, used, cap, first, test);
    }

    // batch.h's collect_boxes: up to kLanesBoxesMax boxes 8 rays per vector
    // against every box, more under the unions. Mrays/s, instanced scenes
    // (simdbvh_bench_scene_desc, BVH8 AVX-512, AMD Zen 4, one thread, 262,144
    // rays; the scene's top-level leaves), in lanes -> under unions: room (5)
    // interior closest 8.53 -> 7.52, primary closest 11.09 -> 10.24;
    // instances-16 (two runs, each against the same earlier build in its
    // process) interior closest 1.10x of it in lanes, 0.90x under unions,
    // primary closest 1.11x and 1.07x; instances-32 interior closest 9.37 ->
    // 8.69, primary closest 14.12 -> 15.71; instances-48 8.63 -> 8.46 and 12.13 -> 15.18;
    // instances-100 5.38-5.65 -> 5.91-5.99 (interior). A camera's rays share
    // the unions they hit (branches predicted), incoherent rays do not.
    static constexpr std::size_t kLanesBoxesMax = 16;
    static SIMDBVH_FORCE_INLINE kernels::detail::TreeWalk boxes(std::span<const Ray> rays,
                                                                std::span<const std::uint8_t> live,
                                                                std::span<const Box8> groups, std::size_t count,
                                                                std::pair<float, std::uint32_t>* out, std::size_t used,
                                                                std::size_t cap, std::uint32_t* first) {
        if (count <= kLanesBoxesMax) return boxes_in_lanes(rays, live, groups, count, out, used, cap, first);
        return boxes_under_unions(rays, live, groups, count, out, used, cap, first);
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

}  // namespace simdbvh::kernels::simd
