// Quantized wide nodes (qnode.h): per axis the grid's origin is the lowest
// lower bound of the node's children and the step the smallest power of two
// that spans the node in 255 steps; lower planes round down, upper planes up,
// each checked (and moved by one step while needed) against the dequantized
// value the node test computes, QBoxN::plane.
#include "simdbvh/bvh8/internal/quantize.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include "simdbvh/platform/parallel.h"

namespace simdbvh::bvh8 {

namespace {

constexpr int kMinExp = 1, kMaxExp = 127 + 119;  // 255 * 2^119 < FLT_MAX: every q * step is finite and exact

template <int N>
float plane_of(const BoxN<N>& b, int p, int i) {
    const float* planes[6] = {b.lo_x, b.hi_x, b.lo_y, b.hi_y, b.lo_z, b.hi_z};
    return planes[p][i];
}

}  // namespace

template <int N>
bool quantize_box(const BoxN<N>& box, const ChildN<N>* children, QBoxN<N>& out) {
    out = QBoxN<N>{};
    for (int i = 0; i < N; ++i)
        if (!children[i].is_empty()) out.valid = typename QBoxN<N>::Mask(out.valid | (1u << i));
    for (int a = 0; a < 3; ++a) {
        float lo = 0, hi = 0;
        bool any = false;
        for (int i = 0; i < N; ++i) {
            if (!(out.valid >> i & 1u)) continue;
            const float l = plane_of(box, 2 * a, i), h = plane_of(box, 2 * a + 1, i);
            if (!std::isfinite(l) || !std::isfinite(h) || !(l <= h)) return false;
            lo = any ? std::min(lo, l) : l;
            hi = any ? std::max(hi, h) : h;
            any = true;
        }
        out.origin[a] = lo;
        // The smallest step 2^k with 255 * 2^k >= hi - lo (in double: exact enough to start; the loop corrects).
        const double extent = double(hi) - double(lo);
        int k = extent > 0 ? int(std::ceil(std::log2(extent / 255.0))) : kMinExp - 127;
        k = std::max(k - 1, kMinExp - 127);  // one lower: the loop below moves up when 255 steps are not enough
        for (;; ++k) {
            if (k + 127 > kMaxExp) return false;
            out.exp[a] = std::uint8_t(k + 127);
            bool fits = true;
            for (int i = 0; i < N && fits; ++i) {
                if (!(out.valid >> i & 1u)) {
                    out.q[2 * a * N + i] = 0;
                    out.q[(2 * a + 1) * N + i] = 0;
                    continue;
                }
                const float l = plane_of(box, 2 * a, i), h = plane_of(box, 2 * a + 1, i);
                const double step = std::ldexp(1.0, k);
                // Lower plane: the largest q whose dequantized value is <= l (q = 0 gives the origin, <= l).
                int ql = int(std::min(255.0, std::floor((double(l) - double(lo)) / step)));
                out.q[2 * a * N + i] = std::uint8_t(ql);
                while (ql > 0 && out.plane(2 * a, i) > l) out.q[2 * a * N + i] = std::uint8_t(--ql);
                // Upper plane: the smallest q whose dequantized value is >= h.
                int qh = int(std::max(0.0, std::ceil((double(h) - double(lo)) / step)));
                if (qh > 255) {
                    fits = false;
                    break;
                }
                out.q[(2 * a + 1) * N + i] = std::uint8_t(qh);
                while (out.plane(2 * a + 1, i) < h) {
                    if (qh == 255) {
                        fits = false;
                        break;
                    }
                    out.q[(2 * a + 1) * N + i] = std::uint8_t(++qh);
                }
            }
            if (fits) break;
        }
    }
    return true;
}

template <int N>
std::vector<QNodeN<N>> quantize(const NodesN<N>& nodes, int threads) {
    std::vector<QNodeN<N>> q(nodes.size());
    std::atomic<bool> ok{true};
    ParallelOptions po;
    po.pin = false;
    po.grain = 1024;
    parallel_for(
        nodes.size(), threads,
        [&](std::size_t b, std::size_t e) {
            for (std::size_t i = b; i < e; ++i) {
                if (!quantize_box<N>(nodes[i].boxes, nodes[i].children, q[i].boxes)) ok.store(false);
                std::copy(nodes[i].children, nodes[i].children + N, q[i].children);
            }
        },
        po);
    if (!ok.load()) q.clear();
    return q;
}

#define SIMDBVH_QUANTIZE(N)                                                     \
    template bool quantize_box<N>(const BoxN<N>&, const ChildN<N>*, QBoxN<N>&); \
    template std::vector<QNodeN<N>> quantize<N>(const NodesN<N>&, int);
SIMDBVH_QUANTIZE(4)
SIMDBVH_QUANTIZE(8)
SIMDBVH_QUANTIZE(16)
#undef SIMDBVH_QUANTIZE

}  // namespace simdbvh::bvh8
