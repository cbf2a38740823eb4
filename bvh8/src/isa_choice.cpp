// The wide traversal's ISA chosen by speed: a short calibration on the first
// large batch, cached per process (where AVX-512 is slower than AVX2 on a
// CPU, the default must not pick it).
#include "simdbvh/bvh8/internal/isa_choice.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "simdbvh/kernels/error.h"

namespace simdbvh::bvh8::detail {
namespace {

constexpr int kUnknown = -1, kCalibrating = -2;
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

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n == 0 ? 0.0 : (n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]));
}

}  // namespace

Isa current_isa(int width, bool any_hit) {
    if (const auto f = forced_isa()) return *f;
    const int s = slot(width, any_hit).state.load(std::memory_order_acquire);
    return s >= 0 ? static_cast<Isa>(s) : detected_isa();
}

std::vector<Range> calibration_groups(std::size_t rays, std::size_t isas) {
    if (isas == 0 || rays < kIsaCalibrationRays) return {};
    const std::size_t a = kCalibrationAlign, budget = rays / 64;  // rays traced again, at most
    // The most cycles (up to kCalibrationCycles, at least 2) whose groups of
    // 32 rays, traced again by each candidate, fit in the budget; then the
    // groups as large as it allows, up to kCalibrationBlock.
    std::size_t cycles = kCalibrationCycles;
    while (cycles > 2 && (1 + cycles * isas) * isas * a > budget) cycles /= 2;
    const std::size_t groups = 1 + cycles * isas;
    const std::size_t block = std::clamp(budget / (groups * isas) / a * a, a, kCalibrationBlock);
    // In kCalibrationClusters runs of consecutive groups, each in the middle
    // of its share of the batch (the rays of a primary image differ from row
    // to row): a run breaks the batch's pieces once and starts in a cold
    // cache once (spread one by one, the groups cost the dragon's 65,536-ray
    // camera batch 1.1-1.8% on one thread, 1.2-1.9% on two; in runs of
    // three, 0.8-1.0% and 0.8-1.8%).
    const std::size_t per = (groups + kCalibrationClusters - 1) / kCalibrationClusters;
    std::vector<Range> out;
    for (std::size_t c = 0; c < kCalibrationClusters; ++c) {
        // Centred in share c, down to a multiple of the alignment (a run,
        // at most rays / 64 / isas rays, is far narrower than a share).
        const std::size_t n = std::min(per, groups - out.size());
        const std::size_t b = ((2 * c + 1) * rays / (2 * kCalibrationClusters) - n * block / 2) / a * a;
        for (std::size_t j = 0; j < n; ++j) out.push_back({b + j * block, b + (j + 1) * block});
    }
    return out;
}

Calibration::Calibration(int width, bool any_hit, std::size_t rays) : width_(width), any_hit_(any_hit) {
    if (rays < kIsaCalibrationRays || forced_isa()) return;
    Slot& s = slot(width, any_hit);
    if (s.state.load(std::memory_order_acquire) != kUnknown) return;
    std::vector<Isa> cands = candidates();
    if (cands.size() < 2) return;
    int expected = kUnknown;
    if (!s.state.compare_exchange_strong(expected, kCalibrating, std::memory_order_acq_rel)) return;
    claimed_ = true;
    cands_ = std::move(cands);
    groups_ = calibration_groups(rays, cands_.size());
}

Calibration::~Calibration() {
    if (claimed_ && !done_) slot(width_, any_hit_).state.store(kUnknown, std::memory_order_release);
}

void Calibration::run(const std::function<void(Isa, std::size_t, std::size_t)>& trace) {
    if (!claimed_ || done_) return;
    const std::size_t k_isas = cands_.size();
    const Isa widest = cands_.back();
    // ns[g][isa]: group g's time per ray with isa. The group is traced first
    // with the widest ISA, not timed (its hits are the batch's): the tree's
    // nodes for those rays come into the cache, which the first batch of a
    // process finds cold (there the first of two ISAs timed on the same or
    // neighbouring rays took 1.3-1.6x the second, whichever it was). Then
    // every candidate traces the same rays, timed, the order rotating from
    // group to group: over a cycle of k_isas groups every candidate takes
    // every place once. So the ISAs are timed where they differ, on rays
    // whose nodes are in the cache (the dragon's 256 x 256 camera: AVX2
    // 1.2-1.3x AVX-512's time there, 1.04-1.06x over the whole batch, whose
    // waits for memory are the same for both). Timing them on neighbouring
    // rays instead (no ray traced twice) misjudged: adjacent blocks of that
    // camera's rays or of sorted bounces differ in cost by up to 2.5x, the
    // same from run to run.
    std::vector<std::array<double, 3>> ns(groups_.size(), std::array<double, 3>{});
    for (std::size_t g = 0; g < groups_.size(); ++g) {
        const auto [b, e] = groups_[g];
        trace(widest, b, e);
        for (std::size_t k = 0; k < k_isas; ++k) {
            const Isa isa = cands_[(g + k) % k_isas];
            const auto t0 = std::chrono::steady_clock::now();
            trace(isa, b, e);
            ns[g][int(isa)] =
                std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count() / double(e - b);
        }
    }
    // Per cycle (group 0 is the warm-up: first calls of each ISA's code), the
    // geometric mean over its groups of each candidate's time ratio to the
    // widest's. A candidate other than the widest takes the choice when the
    // median over cycles is below kMargin and it is faster in all cycles but
    // an eighth of them (a block that a preemption stretched is an outlier,
    // not a verdict; where the ISAs are within a few percent, the widest stays).
    const std::size_t n_cycles = (groups_.size() - 1) / k_isas;
    Isa best = widest;
    double best_ratio = 1.0;
    for (Isa isa : cands_) {
        std::vector<double> cycles;
        for (std::size_t c = 0; c < n_cycles; ++c) {
            double log_sum = 0;
            for (std::size_t j = 0; j < k_isas; ++j) {
                const std::size_t g = 1 + c * k_isas + j;
                log_sum += std::log(std::max(ns[g][int(isa)], 1e-3) / std::max(ns[g][int(widest)], 1e-3));
            }
            cycles.push_back(std::exp(log_sum / double(k_isas)));
        }
        const std::size_t wins =
            std::size_t(std::count_if(cycles.begin(), cycles.end(), [](double x) { return x < 1.0; }));
        const double r = median(cycles);
        if (r < kMargin && wins >= n_cycles - n_cycles / 8 && r < best_ratio) {
            best = isa;
            best_ratio = r;
        }
    }
    Slot& s = slot(width_, any_hit_);
    TraversalIsaChoice& ch = s.choice;
    ch.isa = best;
    ch.calibrated = true;
    ch.rays_timed = 0;
    for (std::size_t g = 1; g < groups_.size(); ++g) ch.rays_timed += groups_[g].end - groups_[g].begin;
    for (Isa isa : cands_) {
        std::vector<double> v;
        for (std::size_t g = 1; g < groups_.size(); ++g) v.push_back(ns[g][int(isa)]);
        ch.ns_per_ray[int(isa)] = median(v);
    }
    done_ = true;
    s.state.store(int(best), std::memory_order_release);
}

void forget_choice(int width, bool any_hit) {
    Slot& s = slot(width, any_hit);
    int state = s.state.load(std::memory_order_acquire);
    while (state >= 0 && !s.state.compare_exchange_weak(state, kUnknown, std::memory_order_acq_rel)) {}
}

bool calibrate(int width, bool any_hit, std::size_t rays,
               const std::function<void(Isa, std::size_t, std::size_t)>& trace) {
    Calibration c(width, any_hit, rays);
    if (!c) return false;
    c.run(trace);
    return true;
}

}  // namespace simdbvh::bvh8::detail

namespace simdbvh {

TraversalIsaChoice traversal_isa_choice(int width, bool any_hit) {
    if (width != 4 && width != 8 && width != 16)
        throw Error("node widths: 4, 8, 16 (got " + std::to_string(width) + ")");
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
