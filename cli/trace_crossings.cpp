// trace --query count | all (see trace_crossings.h).
#include "trace_crossings.h"

#include <chrono>
#include <iostream>
#include <vector>

#include "common.h"
#include "simdbvh/query/crossings.h"
#include "simdbvh/platform/parallel.h"
#include "simdbvh/io/crossing_files.h"
#include "simdbvh/io/output.h"

namespace simdbvh::cli {

void trace_crossings(const Mesh& mesh, std::span<const Ray> rays, const MethodSpec& spec, const CrossingQuery& q,
                     const std::string& out) {
    const bool brute = spec.method == "brute";
    const auto t0 = std::chrono::steady_clock::now();
    Bvh2 bvh;
    if (!brute) bvh = Bvh2::build(mesh, spec.build);
    const double build_ms = seconds_since(t0) * 1e3;
    const auto t1 = std::chrono::steady_clock::now();
    std::vector<unsigned char> bytes;
    std::uint64_t crossings = 0, dropped = 0;
    if (q.all) {
        std::vector<AllHits> all(rays.size());
        parallel_for(rays.size(), spec.threads, [&](std::size_t b, std::size_t e) {
            for (std::size_t i = b; i < e; ++i)
                all[i] = brute ? brute_force_intersect_all(mesh, rays[i], q.cap) : intersect_all(bvh, rays[i], q.cap);
        });
        for (const AllHits& a : all) {
            crossings += a.hits.size();
            dropped += a.dropped;
        }
        bytes = io::encode_all_hits(all);
    } else {
        std::vector<CrossingCount> counts(rays.size());
        if (brute) {
            parallel_for(rays.size(), spec.threads, [&](std::size_t b, std::size_t e) {
                for (std::size_t i = b; i < e; ++i) counts[i] = brute_force_count_crossings(mesh, rays[i]);
            });
        } else {
            count_crossings(bvh, rays, counts, spec.threads);
        }
        for (const CrossingCount& c : counts) crossings += c.crossings;
        bytes = io::encode_counts(counts);
    }
    const double secs = seconds_since(t1);
    io::write_file_atomic(out, bytes);
    std::cout << "method " << (brute ? "brute" : "bvh2") << "  query " << (q.all ? "all" : "count") << "  threads "
              << spec.threads << "\n"
              << "rays " << rays.size() << "  crossings " << crossings;
    if (q.all) std::cout << "  dropped beyond --max-hits " << q.cap << ": " << dropped;
    std::cout << "\nbuild " << build_ms << " ms  trace " << secs * 1e3 << " ms  "
              << (secs > 0 ? double(rays.size()) / secs / 1e6 : 0.0) << " Mrays/s\n"
              << "wrote " << (q.all ? bytes.size() / 20 : rays.size()) << " records to " << out << "\n";
}

}  // namespace simdbvh::cli
