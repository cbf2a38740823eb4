// The point queries' visiting order (query/internal/simdbvh/query/internal/point_query-inl.h
// morton_order): a permutation, sorted by 30-bit Morton code (x in the
// highest of each 3 bits), ties in input order, non-finite points last. The
// order never changes a result, only the speed, so only this test can see it.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>
#include <vector>

#include "simdbvh/query/internal/point_query-inl.h"

namespace simdbvh {
namespace {

TEST(MortonOrder, CubeCornersInZOrderThenTiesThenNonFinite) {
    std::vector<Vec3> pts;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    // The 8 corners of [0, 1]^3, reversed; their codes are x << 2 | y << 1 | z
    // repeated in every bit triple, so z order is the corners' binary order.
    for (int c = 7; c >= 0; --c) pts.push_back({float(c >> 2 & 1), float(c >> 1 & 1), float(c & 1)});
    pts.push_back({nan, 0, 0});  // 8: last
    pts.push_back({0, 0, 0});    // 9: ties with 7, after it
    pts.push_back({1, 1, 1});    // 10: ties with 0, after it
    const std::vector<std::uint32_t> order = detail::morton_order(pts);
    const std::vector<std::uint32_t> want = {7, 9, 6, 5, 4, 3, 2, 1, 0, 10, 8};
    EXPECT_EQ(order, want);
}

TEST(MortonOrder, ManyPointsArePermutedAndSortedByCode) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-5.0f, 5.0f);
    std::vector<Vec3> pts(70000);
    for (Vec3& p : pts) {  // x in [-5, -1] or [1, 5]: which half of the bounds is unambiguous
        const float x = u(rng);
        p = {x < 0 ? x * 0.8f - 1.0f : x * 0.8f + 1.0f, u(rng), u(rng)};
    }
    pts[0].x = -5.0f;
    pts[1].x = 5.0f;
    for (std::size_t i = 2000; i < pts.size(); i += 1000) pts[i] = pts[i + 1];  // ties
    const std::vector<std::uint32_t> order = detail::morton_order(pts);
    std::vector<std::uint32_t> sorted = order;
    std::sort(sorted.begin(), sorted.end());
    for (std::uint32_t i = 0; i < sorted.size(); ++i) ASSERT_EQ(sorted[i], i);
    // Along the order, the half of the bounds in x never goes back (the
    // highest x bit is the code's top bit), and tied points keep their order.
    int last_half = 0;
    for (std::size_t k = 0; k < order.size(); ++k) {
        const int half = pts[order[k]].x >= 0.0f ? 1 : 0;
        ASSERT_GE(half, last_half) << k;
        last_half = half;
    }
    std::vector<std::size_t> pos(order.size());
    for (std::size_t k = 0; k < order.size(); ++k) pos[order[k]] = k;
    for (std::size_t i = 2000; i < pts.size(); i += 1000) EXPECT_LT(pos[i], pos[i + 1]) << "tie " << i;
}

TEST(MortonOrder, ThreadsGiveTheOneThreadOrder) {
    // Enough points for 2 and 3 chunks (one per 2^16 points at least), with
    // ties across chunk boundaries and non-finite points spread through.
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::vector<Vec3> pts(200003);
    for (Vec3& p : pts) p = {u(rng), u(rng), u(rng)};
    for (std::size_t i = 0; i + 70001 < pts.size(); i += 997) pts[i + 70001] = pts[i];  // ties far apart
    for (std::size_t i = 5; i < pts.size(); i += 40009) pts[i].y = std::numeric_limits<float>::quiet_NaN();
    pts[123456] = {std::numeric_limits<float>::infinity(), 0, 0};
    const std::vector<std::uint32_t> one = detail::morton_order(pts, 1);
    EXPECT_EQ(detail::morton_order(pts, 2), one);
    EXPECT_EQ(detail::morton_order(pts, 3), one);
    // Non-finite points last, in input order.
    const std::vector<std::uint32_t> tail(one.end() - 6, one.end());
    EXPECT_EQ(tail, (std::vector<std::uint32_t>{5, 40014, 80023, 120032, 123456, 160041}));
}

}  // namespace
}  // namespace simdbvh
