#pragma once
// trace --query count | all: crossing counts and all hits (BVH2 or brute force).
#include <span>
#include <string>

#include "methods.h"
#include "simdbvh/kernels/ray.h"
#include "simdbvh/kernels/mesh.h"

namespace simdbvh::cli {

struct CrossingQuery {
    bool all = false;        // all hits (else counts)
    std::size_t cap = 1024;  // --max-hits
};

// Runs the query, writes `out`, prints the summary. spec.method: bvh2 or brute.
void trace_crossings(const Mesh& mesh, std::span<const Ray> rays, const MethodSpec& spec, const CrossingQuery& q,
                     const std::string& out);

}  // namespace simdbvh::cli
