#pragma once
// Whether a wide tree's intersect/occluded (bvh8.h) trace a batch in a sorted
// order (TraceOptions::reorder: `on`, or `automatic` and the batch's rays
// scattered from surfaces, the rule of bvh8/internal/simdbvh/bvh8/internal/ray_order.h), for callers
// that build a batch's Ray records in pieces: sorting pays only over the
// whole batch (the Python module builds one Ray array for a batch that sorts,
// and converts and traces 16,384 rays at a time otherwise, so those stay in
// cache: a camera's rays converted whole ran 7-10% slower). Defined for
// N = 4, 8, 16.
#include <cstddef>
#include <functional>
#include <span>

#include "simdbvh/bvh8/bvh8.h"

namespace simdbvh {

template <int N>
bool traces_sorted(const BvhN<N>& bvh, std::span<const Ray> rays, const TraceOptions& opts = {});
// The same for a batch of n rays given by ray_at(i), i < n, before they are
// Ray records (the rule reads about 6,000 of them).
template <int N>
bool traces_sorted(const BvhN<N>& bvh, std::size_t n, const std::function<Ray(std::size_t)>& ray_at,
                   const TraceOptions& opts = {});

}  // namespace simdbvh
