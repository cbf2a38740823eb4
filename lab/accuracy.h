#pragma once
// Accuracy of a method on a sample of rays against the brute-force reference.
#include <span>

#include "lab.h"
#include "simdbvh/reference/classify.h"

namespace simdbvh::lab {

using Tally = reference::Tally;

// Compares hits with the float brute force on the same rays; where they
// differ, both are classified against the double-precision reference
// (reference::compare_methods). Any hit: hit/miss only.
Tally classify_sample(const Mesh& mesh, std::span<const Ray> rays, std::span<const Hit> reference,
                      std::span<const Hit> hits, bool any_hit);

}  // namespace simdbvh::lab
