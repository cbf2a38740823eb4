#pragma once
// The cost model behind Accel's automatic choice (--method auto): the time to
// answer a batch of rays with one method, build included, predicted from the
// triangle count and the ray count by a small formula per method whose
// coefficients were fitted to `simdbvh bench --sweep` on one machine, one set
// per ISA (src/cost_model_fit.cpp holds them and names the command; the sweep:
// docs/results.md#where-brute-force-the-bvh2-and-the-wide-trees-win---method-auto).
//
//   time_ms = build_ms * (1 - build_par + build_par / build_threads) + call_ms
//           + rays * (ray0 + ray1 * f(n)) / threads + rays * ray2 * h(n)
//   build_ms = build0 + build1 * g(n)   g: n log2(n+1) for the trees, n for brute8, 0 for brute
//   ray_ms   = ray0   + ray1   * f(n)   f: log2(n+1) for the trees, n for brute and brute8
//            + ray2 * h(n)                h: brute and brute8 only, n when the triangles do not fit
//                                            the last-level cache (n > llc / bytes per triangle), else 0
//
// build_par is the parallel fraction of the build (Amdahl), fitted from the
// sweep's one- and all-core builds of the larger fit scenes (>= 50,000
// triangles). build_threads is `threads`, except for the trees' builds of
// fewer than 32,768 triangles, which run on one thread (kernels/build_threads.h). The memory term
// is kept whole (not divided by the threads), a conservative choice for cores
// that share the memory bus.
//
// h is the cache cliff of the brute forces: the triangles are streamed once
// per ray (scalar brute force) or once per tile of 16 rays (brute8's tiled
// loop), so past the cache each ray pays extra per triangle; a cyclic stream
// just larger than an LRU cache misses on every line, so the cliff is a step.
// (The old note here, "two threads of brute8 over the dragon took as long as
// one", was a chunking defect, fixed: below 2,048 rays the trace was one chunk
// on one thread.) The cache size is this machine's (topology(): L3, else L2,
// else 8 MiB), so a model fitted on one machine moves its cliff to another's.
//
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "simdbvh/kernels/isa.h"

namespace simdbvh {

enum class AccelMethod : std::uint8_t { brute, brute8, bvh2, bvh4, bvh8, bvh16 };
inline constexpr std::size_t kAccelMethodCount = 6;
inline constexpr AccelMethod kAccelMethods[kAccelMethodCount] = {AccelMethod::brute, AccelMethod::brute8,
                                                                 AccelMethod::bvh2,  AccelMethod::bvh4,
                                                                 AccelMethod::bvh8,  AccelMethod::bvh16};
// The method registry: every method's name, its parse, and its tree width; the library, the CLI, the lab and
// the Python module name and parse methods through these alone.
std::string_view name(AccelMethod m);
std::optional<AccelMethod> parse_accel_method(std::string_view s);
bool is_tree(AccelMethod m);
bool is_wide(AccelMethod m);    // bvh4, bvh8, bvh16
int tree_width(AccelMethod m);  // 2 for bvh2, 4, 8 or 16 for the wide trees, 0 for the brute forces
// "a, b or c": the names of the methods `keep` accepts, for messages.
template <class Keep>
std::string method_names(Keep keep) {
    std::string s, last;
    for (AccelMethod m : kAccelMethods) {
        if (!keep(m)) continue;
        if (!last.empty()) s += s.empty() ? "'" + last + "'" : ", '" + last + "'";
        last = std::string(name(m));
    }
    return s.empty() ? "'" + last + "'" : s + " or '" + last + "'";
}

struct MethodCost {  // milliseconds; see the formula above
    double build0 = 0, build1 = 0, call = 0, ray0 = 0, ray1 = 0, ray2 = 0;
    double build_par = 0;  // parallel fraction of the build, in [0, 1]
};

struct CostModel {
    Isa isa = Isa::scalar;                             // the ISA the coefficients were measured with
    std::array<MethodCost, kAccelMethodCount> cost{};  // indexed by AccelMethod
};

// The fitted model for `isa`; an ISA without a fitted set of its own uses the
// nearest narrower one that has one (model.isa says which).
const CostModel& cost_model(Isa isa);

// The formula's two size terms, shared by the prediction and the fit.
double build_size_term(AccelMethod m, std::size_t triangles);  // g(n)
double ray_size_term(AccelMethod m, std::size_t triangles);    // f(n)
double ray_cache_term(AccelMethod m, std::size_t triangles);   // h(n)
// The triangles the last-level cache holds for a brute force (llc / bytes per triangle).
std::size_t brute_cache_triangles(AccelMethod m);
double predict_ms(const CostModel& model, AccelMethod m, std::size_t triangles, std::size_t rays, int threads = 1);

struct AccelChoice {
    AccelMethod method = AccelMethod::bvh8;
    Isa isa = Isa::scalar;  // the ISA whose coefficients were used
    std::size_t triangles = 0, rays = 0;
    int threads = 1;
    std::array<double, kAccelMethodCount> predicted_ms{};  // indexed by AccelMethod
};

// The method with the smallest predicted time (ties: the earlier in
// kAccelMethods), except that a wide tree is BVH8 unless another width is
// predicted faster by more than 8% of BVH8's build (the widths' build terms
// are not known that closely; cost_model.cpp).
AccelChoice choose(const CostModel& model, std::size_t triangles, std::size_t rays, int threads = 1);
// "bvh8: predicted 12.3 ms for 1000000 rays on 871414 triangles (1 thread, avx512 model); brute 1.2e+06 ms, ..."
std::string describe(const AccelChoice& c);

}  // namespace simdbvh
