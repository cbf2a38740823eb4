#pragma once
// Shared by the wide trees' option tests (packets_test.cpp, reorder_test.cpp):
// a batch traced with some TraceOptions on one ISA gives `want`'s closest hits
// bit for bit, and an any hit exactly where `want` has a hit.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "simdbvh/bvh8/bvh8.h"

namespace simdbvh::test::wide {

// Fills `any` with the batch's any hits (for the caller's further checks).
template <int N>
void expect_hits(const BvhN<N>& bvh, const std::vector<Ray>& rays, const std::vector<Hit>& want, const TraceOptions& o,
                 Isa isa, const std::string& how, std::vector<Hit>& any) {
    std::vector<Hit> got(rays.size());
    any.assign(rays.size(), Hit{});
    intersect(bvh, rays, got, with_isa(o, isa));
    occluded(bvh, rays, any, with_isa(o, isa));
    for (std::size_t i = 0; i < rays.size(); ++i) {
        ASSERT_EQ(got[i], want[i]) << how << " ray " << i;
        ASSERT_EQ(any[i].hit(), want[i].hit()) << how << " any, ray " << i;
    }
}

}  // namespace simdbvh::test::wide
