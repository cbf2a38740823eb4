#pragma once
// Internal: the wide traversal's choice of ISA by speed (bvh8.h,
// "Without it, the ISA is chosen by speed"). One slot per (width, query):
// unknown -> calibrating (one thread) -> the chosen ISA.
#include <cstddef>
#include <functional>

#include "simdbvh/bvh8/bvh8.h"

namespace simdbvh::bvh8::detail {

// The ISA to use now without calibrating: forced, else calibrated, else detected.
Isa current_isa(int width, bool any_hit);

// Calibrates this (width, query) when it has no choice yet, nothing forces an
// ISA, the CPU has two SIMD ISAs, `rays` >= kIsaCalibrationRays and no other
// thread is calibrating it. trace(isa, begin, end) must trace rays [begin, end)
// with `isa` (every candidate traces the same rays, so their hits are final
// whichever ran last). The calibration traces kCalibrationChunks chunks spread
// evenly over the batch (the rays of a primary image differ from row to row);
// returns whether it did (then calibration_chunk(c, rays) are the traced ranges).
inline constexpr std::size_t kCalibrationChunk = 512, kCalibrationChunks = 5;
struct Range {
    std::size_t begin, end;
};
Range calibration_chunk(std::size_t c, std::size_t rays);
bool calibrate(int width, bool any_hit, std::size_t rays,
               const std::function<void(Isa, std::size_t, std::size_t)>& trace);

}  // namespace simdbvh::bvh8::detail
