// The wide traversal's ISA chosen by speed: a short calibration on the first
// large batch, cached per process (issue 13: where AVX-512 is slower than AVX2
// on a CPU, the default must not pick it).
#include "isa_choice.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <string>
#include <vector>

#include "simdbvh/kernels/error.h"

namespace simdbvh::bvh8::detail {
namespace {

constexpr int kUnknown = -1, kCalibrating = -2;
// Chunks each traced with every candidate ISA (the order alternates per
// chunk); the first chunk is an untimed warm-up.
constexpr std::size_t kChunk = kCalibrationChunk, kChunks = kCalibrationChunks;
static_assert(kChunk * kChunks <= kIsaCalibrationRays);
// The widest ISA keeps the choice unless another is more than this much faster.
constexpr double kMargin = 0.97;

struct Slot {
    std::atomic<int> state{kUnknown};
    TraversalIsaChoice choice;  // written before state is released
};

Slot& slot(int width, bool any_hit) {
    static Slot slots[3][2];
    const int w = width == 4 ? 0 : (width == 8 ? 1 : 2);
    return slots[w][any_hit ? 1 : 0];
}

std::vector<Isa> candidates() {
    std::vector<Isa> out;
    for (Isa isa : supported_isas())
        if (isa != Isa::scalar) out.push_back(isa);
    return out;
}

}  // namespace

Isa current_isa(int width, bool any_hit) {
    if (const auto f = forced_isa()) return *f;
    const int s = slot(width, any_hit).state.load(std::memory_order_acquire);
    return s >= 0 ? static_cast<Isa>(s) : detected_isa();
}

Range calibration_chunk(std::size_t c, std::size_t rays) {
    const std::size_t b = c * (rays / kChunks);  // rays >= kIsaCalibrationRays: the chunks never overlap
    return {b, b + kChunk};
}

bool calibrate(int width, bool any_hit, std::size_t rays,
               const std::function<void(Isa, std::size_t, std::size_t)>& trace) {
    if (rays < kIsaCalibrationRays || forced_isa()) return false;
    Slot& s = slot(width, any_hit);
    if (s.state.load(std::memory_order_acquire) != kUnknown) return false;
    const std::vector<Isa> cands = candidates();
    if (cands.size() < 2) return false;
    int expected = kUnknown;
    if (!s.state.compare_exchange_strong(expected, kCalibrating, std::memory_order_acq_rel)) return false;
    // t[isa][c]: chunk c's time with isa. Per chunk, the ratio to the widest
    // ISA's time on the same rays; the median ratio decides (a chunk that a
    // preemption stretched is an outlier, not a verdict).
    double t[3][kChunks] = {};
    try {
        for (std::size_t c = 0; c < kChunks; ++c) {
            const auto [b, e] = calibration_chunk(c, rays);
            for (std::size_t k = 0; k < cands.size(); ++k) {
                const Isa isa = cands[c % 2 == 0 ? k : cands.size() - 1 - k];
                const auto t0 = std::chrono::steady_clock::now();
                trace(isa, b, e);
                t[int(isa)][c] = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count();
            }
        }
    } catch (...) {
        s.state.store(kUnknown, std::memory_order_release);
        throw;
    }
    auto median_timed = [&](auto value) {  // over chunks 1..kChunks-1 (chunk 0 is the warm-up)
        std::vector<double> v;
        for (std::size_t c = 1; c < kChunks; ++c) v.push_back(value(c));
        std::sort(v.begin(), v.end());
        const std::size_t n = v.size();
        return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
    };
    const Isa widest = cands.back();
    Isa best = widest;
    double best_ratio = 1.0;
    for (Isa isa : cands) {
        const double r = median_timed([&](std::size_t c) { return t[int(isa)][c] / t[int(widest)][c]; });
        if (r < kMargin && r < best_ratio) {
            best = isa;
            best_ratio = r;
        }
    }
    TraversalIsaChoice& ch = s.choice;
    ch.isa = best;
    ch.calibrated = true;
    ch.rays_timed = kChunk * (kChunks - 1);
    for (Isa isa : cands) ch.ns_per_ray[int(isa)] = median_timed([&](std::size_t c) { return t[int(isa)][c]; }) / double(kChunk);
    s.state.store(int(best), std::memory_order_release);
    return true;
}

}  // namespace simdbvh::bvh8::detail

namespace simdbvh {

TraversalIsaChoice traversal_isa_choice(int width, bool any_hit) {
    if (width != 4 && width != 8 && width != 16) throw Error("node widths: 4, 8, 16 (got " + std::to_string(width) + ")");
    TraversalIsaChoice out;
    if (const auto f = forced_isa()) {
        out.isa = *f;
        out.forced = true;
        return out;
    }
    bvh8::detail::Slot& s = bvh8::detail::slot(width, any_hit);
    if (s.state.load(std::memory_order_acquire) >= 0) return s.choice;
    out.isa = detected_isa();
    return out;
}

}  // namespace simdbvh
