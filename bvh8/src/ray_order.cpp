// The traced order of a wide tree's batch (ray_order.h): keys and an LSD radix sort.
#include "simdbvh/bvh8/internal/ray_order.h"

#include <algorithm>
#include <array>
#include <bitset>
#include <cmath>
#include <utility>

namespace simdbvh::bvh8::detail {

namespace {

// 6 bits spread to every third bit of 18.
std::uint32_t spread6(std::uint32_t x) {
    x = (x | (x << 8)) & 0x0000F00Fu;
    x = (x | (x << 4)) & 0x000C30C3u;
    x = (x | (x << 2)) & 0x00049249u;
    return x;
}

// A coordinate's cell in [0, 63]; NaN (and anything not above lo) to 0.
std::uint32_t cell(float x, float lo, float scale) {
    const float f = (x - lo) * scale;
    return f > 0.0f ? (f < 63.0f ? std::uint32_t(f) : 63u) : 0u;
}

struct Grid {
    Vec3 lo{0, 0, 0}, scale{0, 0, 0};
    explicit Grid(const Aabb& b) {
        if (b.is_empty()) return;
        lo = b.lo;
        const Vec3 e = b.extent();
        // 64 / extent, 0 for a flat (or infinite) axis: every ray in one cell along it.
        auto s = [](float ext) { return ext > 0.0f && std::isfinite(ext) ? 64.0f / ext : 0.0f; };
        scale = {s(e.x), s(e.y), s(e.z)};
    }
    std::uint32_t key(const Ray& r) const {
        const std::uint32_t m = spread6(cell(r.org.x, lo.x, scale.x)) | (spread6(cell(r.org.y, lo.y, scale.y)) << 1) |
                                (spread6(cell(r.org.z, lo.z, scale.z)) << 2);
        const std::uint32_t oct = std::uint32_t(std::signbit(r.dir.x)) | (std::uint32_t(std::signbit(r.dir.y)) << 1) |
                                  (std::uint32_t(std::signbit(r.dir.z)) << 2);
        // The top 9 bits of the 18-bit Morton code are the 8^3 cell's code.
        return ((m >> 9) << 12) | (oct << 9) | (m & 511u);
    }
};

constexpr int kDigitBits = 7;
constexpr int kPasses = 3;  // 21 bits: the key
constexpr std::size_t kBuckets = std::size_t(1) << kDigitBits;
constexpr std::size_t kPairs = 1024;    // scattered(): consecutive pairs for (1)
constexpr std::size_t kSamples = 4096;  // and rays for (2) and (3)

}  // namespace

std::uint32_t ray_key(const Ray& ray, const Aabb& bounds) { return Grid(bounds).key(ray); }

namespace {

template <class At>
bool scattered_at(std::size_t n, const At& ray_at, const Aabb& bounds) {
    if (n < 2) return false;
    const Grid g(bounds);
    // (1) on kPairs pairs first: most batches that keep their order (a camera's) stop here.
    const std::size_t pairs = std::min(kPairs, n - 1);
    const std::size_t step = (n - 1) / pairs;
    std::size_t changes = 0;
    for (std::size_t k = 0; k < pairs; ++k) {
        const std::size_t i = k * step;
        changes += (g.key(ray_at(i)) >> kFineBits) != (g.key(ray_at(i + 1)) >> kFineBits);  // cell or octant
    }
    const bool ordered = 4 * changes <= pairs;
    // (2) and (3) on kSamples rays.
    const std::size_t samples = std::min(kSamples, n);
    const std::size_t stride = n / samples;
    std::size_t inside = 0;
    std::bitset<512> cells;
    for (std::size_t k = 0; k < samples; ++k) {
        const Ray r = ray_at(k * stride);
        const Vec3 o = r.org;
        if (bounds.lo.x <= o.x && o.x <= bounds.hi.x && bounds.lo.y <= o.y && o.y <= bounds.hi.y &&
            bounds.lo.z <= o.z && o.z <= bounds.hi.z) {
            ++inside;
            cells.set(g.key(r) >> (kFineBits + 3));
        }
    }
    if (!(2 * inside >= samples && 4 * cells.count() < 3 * cells.size() && n >= kReorderRaysPerCell * cells.count()))
        return false;
    // An order that keeps neighbours together is kept only when the rays share an origin (a camera or a
    // LiDAR inside the bounds: a few cells); rays from many surface points in pixel order (shadow rays toward
    // one light) are sorted all the same: the sort's 3-D neighbourhoods keep a stream of 32 closer together
    // than an image row does.
    return !ordered || cells.count() > kReorderSharedOriginCells;
}

}  // namespace

bool scattered(std::span<const Ray> rays, const Aabb& bounds) {
    return scattered_at(
        rays.size(), [&](std::size_t i) -> const Ray& { return rays[i]; }, bounds);
}
bool scattered(std::size_t n, const std::function<Ray(std::size_t)>& ray_at, const Aabb& bounds) {
    return scattered_at(n, ray_at, bounds);
}

void sort_rays(std::span<const Ray> rays, const Aabb& bounds, std::vector<std::uint64_t>& order,
               std::vector<std::uint64_t>& work) {
    const std::size_t n = rays.size();
    const Grid g(bounds);
    order.resize(n);
    work.resize(n);
    std::array<std::array<std::uint32_t, kBuckets>, kPasses> count{};
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint32_t key = g.key(rays[i]);
        order[i] = (std::uint64_t(key) << kReorderIndexBits) | i;
        for (int p = 0; p < kPasses; ++p) ++count[p][(key >> (p * kDigitBits)) & (kBuckets - 1)];
    }
    for (int p = 0; p < kPasses; ++p) {
        const int shift = kReorderIndexBits + p * kDigitBits;
        auto& c = count[p];
        if (c[(order[0] >> shift) & (kBuckets - 1)] == n) continue;  // one digit for every ray: nothing moves
        std::uint32_t sum = 0;
        for (auto& b : c) sum += std::exchange(b, sum);
        for (std::size_t i = 0; i < n; ++i) work[c[(order[i] >> shift) & (kBuckets - 1)]++] = order[i];
        order.swap(work);
    }
}

}  // namespace simdbvh::bvh8::detail
