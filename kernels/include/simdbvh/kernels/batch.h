#pragma once
// Batched kernel entry points: a span of rays against boxes or triangles.
// Each call chooses its implementation once, at the top (one switch on `isa`);
// the ISA defaults to the detected/forced one and can be set explicitly so
// tests and benchmarks can run every path. Unsupported ISA -> simdbvh::Error.
//
// Every implementation (scalar, avx2, avx512) returns bit-identical results:
// the scalar one loops the reference functions of box.h / triangle.h.
// Rays that prepare() marks invalid (zero/NaN/Inf direction, NaN/Inf origin,
// NaN or empty interval) are misses: mask 0 with entries +inf, Hit{}.
// No intrinsics and no xsimd in this header; the test and benchmark forms
// (single-triangle baseline, box counter, last ISA used) are in
// kernels/testing (simdbvh/kernels/testing.h), not installed.
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "simdbvh/kernels/aabb.h"
#include "simdbvh/kernels/hit.h"
#include "simdbvh/kernels/isa.h"
#include "simdbvh/kernels/ray.h"
#include "simdbvh/kernels/soa.h"
#include "simdbvh/kernels/triangle.h"

namespace simdbvh::kernels {

// --- 8-wide forms (SoA blocks; one implementation per ISA) ---
// Each ray's prepare() (ray.h) and its test against `bounds` (box.h's
// intersect_box, the ray's own interval): ok[i] = 1 when ray i is valid and
// hits them (0 for every ray when bounds is null), and then out[i] =
// prepare(rays[i]) bit for bit (out[i] is unspecified where ok[i] = 0). The
// wide traversals start their rays this way, 8 at a time; the SIMD paths
// compute the 8 rays' fields in vector lanes (rays whose direction prepare()
// rescales one at a time).
void prepare_rays(std::span<const Ray> rays, const Aabb* bounds, std::span<PreparedRay> out, std::span<std::uint8_t> ok,
                  Isa isa = active_isa());
// Every ray against one Box8, interval [tmin, tmax] of the ray: masks[i] bit j =
// ray i hits box j; entries[8*i + j] = its entry distance (lanes that miss:
// whatever the slab test computed; invalid rays: +inf).
void intersect_box8(std::span<const Ray> rays, const Box8& boxes, std::span<std::uint8_t> masks,
                    std::span<float> entries, Isa isa = active_isa());
// Every ray against every Box8 of `groups` (ray-major, each ray prepared once):
// masks[G*i + g] bit j = ray i hits box j of group g, entries[8*(G*i + g) + j]
// its entry distance (in the caller's t), G = groups.size(); each group's
// masks and entries are those intersect_box8 gives for it, bit for bit.
void intersect_box8_groups(std::span<const Ray> rays, std::span<const Box8> groups, std::span<std::uint8_t> masks,
                           std::span<float> entries, Isa isa = active_isa());
// The same with a level above, for many groups: lane j of supers[s] holds every
// box of groups[8 * s + j] (groups.size() <= 8 * supers.size()). Each ray tests
// the supers, then only the groups of the super lanes it hits. The masks are
// intersect_box8_groups' bit for bit: a box inside a box the conservative slab
// test misses is missed too (each slab distance is monotone in its plane, and a
// slab is dropped as NaN only where a plane contains the origin, which at the
// inner box leaves a plane no looser than the outer box's). Entries: the same
// where a mask bit is set; +inf throughout the groups a ray does not test.
void intersect_box8_nested(std::span<const Ray> rays, std::span<const Box8> supers, std::span<const Box8> groups,
                           std::span<std::uint8_t> masks, std::span<float> entries, Isa isa = active_isa());
// A tree of Box8 nodes, nodes[0] the root: lane j of node n bounds everything
// under children[8 * n + j], which is kBoxTreeEmpty (an unused lane: never
// reported), an inner node's index m (n < m < nodes.size(), each node the child
// of one lane only), or kBoxTreeLeaf | id (a leaf, id < 2^31). Each ray (with
// live[i] != 0, when `live` is not empty) walks the tree from the root and
// appends to `out` every leaf it reaches, as (entry distance in the caller's t,
// id): ray i's are out[first[i] .. first[i + 1]) (first: rays.size() + 1 values),
// in no particular order. A leaf is reached when the ray hits its lane and the
// lane of every ancestor: with each lane's box holding the boxes below it, that
// is exactly when it hits the leaf's own lane (the argument of _nested above), and
// the entries are those intersect_box8 gives for the leaf's node. Throws
// simdbvh::Error for a malformed tree (sizes, indices, a node reached twice).
inline constexpr std::uint32_t kBoxTreeLeaf = 0x80000000u;
inline constexpr std::uint32_t kBoxTreeEmpty = 0xFFFFFFFFu;
void collect_box8_tree(std::span<const Ray> rays, std::span<const std::uint8_t> live, std::span<const Box8> nodes,
                       std::span<const std::uint32_t> children, std::vector<std::pair<float, std::uint32_t>>& out,
                       std::span<std::uint32_t> first, Isa isa = active_isa());
// Each ray (with live[i] != 0, when `live` is not empty) against every box
// of `boxes`: appends (entry distance in the caller's t, box index) for each
// box it hits, the boxes in index order; ray i's are out[first[i] ..
// first[i + 1]) (first: rays.size() + 1 values). The hits and entries are
// intersect_box's (box.h) per box, so for a tree whose leaves are these boxes
// they are what collect_box8_tree reports. The SIMD paths prepare 8 rays per
// vector; up to 16 boxes they test 8 rays per vector against each box, above
// that each ray against the unions of 8 boxes (two vectors for up to 128
// boxes) and only the groups of 8 boxes whose union it hits (rays with
// rescaled directions against every group). Either beats a tree walk for
// the boxes of a small scene's top level. At most
// kCollectBoxesMax boxes, else simdbvh::Error.
inline constexpr std::size_t kCollectBoxesMax = 128;
void collect_boxes(std::span<const Ray> rays, std::span<const std::uint8_t> live, std::span<const Aabb> boxes,
                   std::vector<std::pair<float, std::uint32_t>>& out, std::span<std::uint32_t> first,
                   Isa isa = active_isa());
// Closest hit of each ray over all blocks (ties: lower prim id); Hit{} on a miss.
// The SIMD loops walk the blocks in L1-sized tiles for kBruteRayTile rays at a
// time (each block is read once per tile): callers that split rays over
// threads keep at least this many rays per call.
inline constexpr std::size_t kBruteRayTile = 16;
void intersect_tri8(std::span<const Ray> rays, std::span<const Tri8> blocks, TriangleTest test, std::span<Hit> hits,
                    Isa isa = active_isa());
// Any hit of each ray over the blocks in [tmin, tmax]: occluded[i] = 0/1.
// When first_hits is not empty it receives the first hit found (blocks in
// order, lanes in order), Hit{} when none.
void occluded_tri8(std::span<const Ray> rays, std::span<const Tri8> blocks, TriangleTest test,
                   std::span<std::uint8_t> occluded, std::span<Hit> first_hits = {}, Isa isa = active_isa());

}  // namespace simdbvh::kernels
