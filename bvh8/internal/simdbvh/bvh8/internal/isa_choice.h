#pragma once
// Internal: the wide traversal's choice of ISA by speed (bvh8.h,
// "Without it, the ISA is chosen by speed"). One slot per (width, query):
// unknown -> calibrating (one thread) -> the chosen ISA.
#include <cstddef>
#include <functional>
#include <vector>

#include "simdbvh/bvh8/bvh8.h"

namespace simdbvh::bvh8::detail {

// The ISA to use now without calibrating: forced, else calibrated, else detected.
Isa current_isa(int width, bool any_hit);

struct Range {
    std::size_t begin, end;
};

// The calibration's rays in a batch of `rays` rays with `isas` candidate ISAs:
// 1 + cycles * isas groups (the first an untimed warm-up), in increasing
// order, disjoint, in kCalibrationClusters runs of consecutive groups spread
// over the batch (the rays of a primary image differ from row to row). Each group is traced with the
// widest ISA (those are its hits), then again by every candidate, timed:
// the rays traced again are at most rays / 64 (1.6%; the rays in the cache
// then, those traces take less than their share of the batch's time), for
// batches below 36,864 rays 320 (two cycles of groups of 32 rays; 3.9% of
// kIsaCalibrationRays). Cycles: up to kCalibrationCycles as the budget
// allows; groups of 32 to kCalibrationBlock rays, starting and ending at
// multiples of kCalibrationAlign, so the rays around and inside them keep
// the batch's streams of 32 (TraceOptions::packets).
inline constexpr std::size_t kCalibrationCycles = 8, kCalibrationBlock = 256, kCalibrationAlign = 32,
                             kCalibrationClusters = 3;
std::vector<Range> calibration_groups(std::size_t rays, std::size_t isas);

// The calibration of one (width, query) slot for one batch. Constructed, it
// claims the slot when the slot has no choice yet, nothing forces an ISA, the
// CPU has two SIMD ISAs, `rays` >= kIsaCalibrationRays and no other thread
// is calibrating it (then it is true). run(trace) traces groups()' rays
// (trace(isa, begin, end): rays [begin, end) with `isa` on the calling
// thread, their hits final whichever ISA ran last), times the candidates
// and stores the choice; the caller traces the other rays (with
// current_isa(): the best detected ISA until run() has stored the choice).
// A claimed slot whose run() never completed (an exception) goes back to
// unknown: a later batch calibrates.
class Calibration {
public:
    Calibration(int width, bool any_hit, std::size_t rays);
    ~Calibration();
    Calibration(const Calibration&) = delete;
    Calibration& operator=(const Calibration&) = delete;
    explicit operator bool() const { return claimed_; }
    const std::vector<Range>& groups() const { return groups_; }
    void run(const std::function<void(Isa, std::size_t, std::size_t)>& trace);

private:
    int width_;
    bool any_hit_;
    bool claimed_ = false, done_ = false;
    std::vector<Isa> cands_;
    std::vector<Range> groups_;
};

// The slot back to unknown (no choice), for the benchmark of the batch that
// calibrates: not while a batch without an ISA traces with this slot.
void forget_choice(int width, bool any_hit);

// Claims and runs a calibration (the batch's other rays are the caller's);
// returns whether it calibrated.
bool calibrate(int width, bool any_hit, std::size_t rays,
               const std::function<void(Isa, std::size_t, std::size_t)>& trace);

}  // namespace simdbvh::bvh8::detail
