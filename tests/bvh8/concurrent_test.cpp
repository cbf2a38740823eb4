// Many threads tracing the same BVH2 and BVH8 at once (run under the tsan
// preset by scripts/tsan.sh): identical hits to a single-threaded trace.
#include <gtest/gtest.h>

#include <thread>

#include "simdbvh/bvh8/bvh8.h"
#include "simdbvh/workloads/rays.h"
#include "simdbvh/workloads/scenes.h"

namespace simdbvh {
namespace {

TEST(Concurrent, ManyThreadsTraceOneBvh) {
    const Mesh mesh = workloads::random_soup(20000, 17);
    const Bvh2 bvh2 = Bvh2::build(mesh);
    const Bvh8 bvh8 = Bvh8::build(bvh2);
    const auto rays = workloads::generate_rays(mesh, workloads::RayKind::incoherent, 4000, 9);
    std::vector<Hit> want(rays.size());
    intersect(bvh2, rays, want);
    constexpr int kThreads = 4;
    std::vector<std::vector<Hit>> got2(kThreads, std::vector<Hit>(rays.size())), got8 = got2;
    std::vector<std::thread> pool;
    for (int k = 0; k < kThreads; ++k)
        pool.emplace_back([&, k] {
            intersect(bvh2, rays, got2[k]);
            intersect(bvh8, rays, got8[k]);
        });
    for (auto& t : pool) t.join();
    // And the library's own split over threads.
    TraceOptions o;
    o.threads = 3;
    std::vector<Hit> split(rays.size());
    intersect(bvh8, rays, split, o);
    for (int k = 0; k < kThreads; ++k)
        for (std::size_t i = 0; i < rays.size(); ++i) {
            ASSERT_EQ(got2[k][i], want[i]) << "thread " << k << " ray " << i;
            ASSERT_EQ(got8[k][i], want[i]) << "thread " << k << " ray " << i;
        }
    for (std::size_t i = 0; i < rays.size(); ++i) ASSERT_EQ(split[i], want[i]) << "ray " << i;
}

// Sorted batches (TraceOptions::reorder): three threads each trace one BVH8
// sorted, each batch's blocks split over two threads of its own (the per-thread
// order and gather arrays), against the BVH2.
TEST(Concurrent, ManyThreadsTraceSortedBatches) {
    const Mesh mesh = workloads::random_soup(20000, 17);
    const Bvh2 bvh2 = Bvh2::build(mesh);
    const Bvh8 bvh8 = Bvh8::build(bvh2);
    const auto rays = workloads::generate_rays(mesh, workloads::RayKind::diffuse, 40000, 9);  // three blocks
    std::vector<Hit> want(rays.size());
    intersect(bvh2, rays, want);
    TraceOptions o;
    o.reorder = Reorder::on;
    o.threads = 2;
    constexpr int kThreads = 3;
    std::vector<std::vector<Hit>> got(kThreads, std::vector<Hit>(rays.size()));
    std::vector<std::thread> pool;
    for (int k = 0; k < kThreads; ++k)
        pool.emplace_back([&, k] {
            for (int pass = 0; pass < 2; ++pass) intersect(bvh8, rays, got[k], o);
        });
    for (auto& t : pool) t.join();
    std::size_t hits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        for (int k = 0; k < kThreads; ++k) ASSERT_EQ(got[k][i], want[i]) << "thread " << k << " ray " << i;
        hits += want[i].hit();
    }
    EXPECT_GT(hits, rays.size() / 20);
}

}  // namespace
}  // namespace simdbvh
