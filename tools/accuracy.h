#pragma once
// Accuracy of a method on a sample of rays against the brute-force reference.
#include <cstddef>
#include <span>

#include "simdbvh/kernels/hit.h"
#include "simdbvh/kernels/ray.h"
#include "simdbvh/mesh.h"

namespace simdbvh::cli {

struct Tally {
    std::size_t agree = 0, tie = 0, leak = 0, false_hit = 0, wrong_triangle = 0, t_error = 0;
    std::size_t total() const { return agree + tie + leak + false_hit + wrong_triangle + t_error; }
    std::size_t disagreements() const { return leak + false_hit + wrong_triangle + t_error; }
    double agreement() const { return total() ? double(agree + tie) / double(total()) : 1.0; }
};

// exact: our own paths must equal the float brute force bit for bit (closest)
// or on hit/miss (any hit); any difference is classified against the
// double-precision reference. Other methods (Embree) are classified against
// the reference wherever they differ from the float brute force.
Tally classify_sample(const Mesh& mesh, std::span<const Ray> rays, std::span<const Hit> reference,
                      std::span<const Hit> hits, bool any_hit, bool exact);

}  // namespace simdbvh::cli
