#pragma once
// Exact inside/outside rows, shared by the BVH2's and the wide
// trees' benches: 100,000 query points uniform in the scene's bounds grown by
// 10%, one +z ray per point, one thread, an untimed warm-up first.
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "simdbvh/query/inside.h"
#include "simdbvh/workloads/points.h"
#include "traversal_fixture.h"

namespace bench {

inline const std::vector<simdbvh::Vec3>& inside_points() {
    static const auto pts = simdbvh::workloads::random_points(traversal_scene().mesh.bounds(), 100000, 9);
    return pts;
}

template <class Tree>
void run_inside(benchmark::State& st, const Tree& tree, const std::string& label) {
    const auto& pts = inside_points();
    std::vector<simdbvh::PointSide> out(pts.size());
    classify_points(tree, pts, out);  // untimed warm-up
    std::size_t inside = 0;
    for (const auto& p : out) inside += p.side == simdbvh::Side::inside;
    for (auto _ : st) {
        classify_points(tree, pts, out);
        benchmark::DoNotOptimize(out.data());
    }
    st.counters["points/s"] = benchmark::Counter(double(pts.size()), benchmark::Counter::kIsIterationInvariantRate);
    st.counters["inside"] = double(inside) / double(pts.size());
    st.SetLabel(label + " exact inside, uniform in the bounds");
}

}  // namespace bench
