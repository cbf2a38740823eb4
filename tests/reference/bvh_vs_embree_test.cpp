// BVH2 and BVH8 (every supported ISA) against Embree 3 (quality medium and
// high, default and robust), closest and any hit, on real and procedural
// scenes and three ray kinds. Where we and Embree differ, both answers are
// classified against the double reference (docs/accuracy.md): no disagreement may be
// ours; Embree's own are reported (stdout and RecordProperty).
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <iomanip>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/bvh8/bvh8.h"
#include "simdbvh/reference/classify.h"
#include "simdbvh/reference/embree.h"
#include "simdbvh/kernels/isa.h"
#include "simdbvh/workloads/rays.h"
#include "simdbvh/workloads/scenes.h"

namespace simdbvh::reference {
namespace {

using workloads::RayKind;

constexpr std::size_t kRays = 3000;  // per ray kind: keeps the suite well under a minute on 2 cores

struct Case {
    std::string scene;
    RayKind kind;
};

std::string case_name(const testing::TestParamInfo<Case>& info) {
    std::string s = info.param.scene + "_" + std::string(workloads::name(info.param.kind));
    for (char& c : s)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return s;
}

bool npm_scene(const std::string& s) { return s == "bunny" || s == "teapot" || s.rfind("dragon", 0) == 0; }

std::string describe(const Ray& r, const Hit& ours, const Hit& theirs, const Disagreement& d) {
    std::ostringstream o;
    o << std::setprecision(9) << "ray " << d.ray << " o=(" << r.org.x << "," << r.org.y << "," << r.org.z << ") d=("
      << r.dir.x << "," << r.dir.y << "," << r.dir.z << ") [" << r.tmin << "," << r.tmax << "]: ours "
      << name(d.a.label) << (d.a.marginal ? " (marginal)" : "") << " prim=" << ours.prim << " t=" << ours.t
      << ", embree " << name(d.b.label) << " prim=" << theirs.prim << " t=" << theirs.t
      << ", reference prim=" << d.ref_prim << " t=" << d.t_ref;
    return o.str();
}

// One comparison: asserts that no disagreement is ours; prints and records
// Embree's own (once per Embree configuration: the same for each of our
// methods, which are bit-identical). A marginal disagreement of ours (the
// reference itself is within float rounding: a ray grazing an edge or a vertex)
// is printed but tolerated; see simdbvh/reference/classify.h.
// strict: not even a marginal disagreement is allowed (closed mesh, rays from inside).
void report(const std::string& method, const std::string& embree, const std::string& mode, const Comparison& c,
            std::span<const Ray> rays, std::span<const Hit> ours, std::span<const Hit> theirs, bool strict) {
    const std::string key = embree + "_" + mode;
    if (method == "bvh2") {
        std::cout << "  " << std::left << std::setw(21) << embree << std::setw(8) << mode
                  << " embree: " << to_string(c.b) << " (" << c.disagreements.size() << " rays differ from ours)\n";
        testing::Test::RecordProperty(key + "_leak", std::to_string(c.b.leak));
        testing::Test::RecordProperty(key + "_false_hit", std::to_string(c.b.false_hit));
        testing::Test::RecordProperty(key + "_wrong_triangle", std::to_string(c.b.wrong_triangle));
        testing::Test::RecordProperty(key + "_t_error", std::to_string(c.b.t_error));
        testing::Test::RecordProperty(key + "_marginal", std::to_string(c.b.marginal));
    }
    if (c.a.disagreements() > 0) {
        std::cout << "  " << std::left << std::setw(21) << embree << std::setw(8) << mode << " " << method << ": "
                  << to_string(c.a) << "\n";
        testing::Test::RecordProperty(method + "_vs_" + key + "_ours_marginal", std::to_string(c.a.marginal));
        std::size_t shown = 0;
        for (const Disagreement& d : c.disagreements) {
            if (is_agreement(d.a.label) || d.a.marginal || shown++ >= 3) continue;  // details of failures only
            const Hit o = ours.empty() ? Hit{} : ours[d.ray], t = theirs.empty() ? Hit{} : theirs[d.ray];
            std::cout << "    " << describe(rays[d.ray], o, t, d) << "\n";
        }
    }
    EXPECT_EQ(c.a.hard_disagreements(), 0u) << method << " vs " << key << ": " << to_string(c.a);
    if (strict) EXPECT_EQ(c.a.disagreements(), 0u) << method << " vs " << key << ": " << to_string(c.a);
}

// Traces every method and every Embree configuration and reports.
void run(const Mesh& mesh, std::span<const Ray> rays, bool strict) {
    struct Method {
        std::string name;
        std::vector<Hit> closest, any;
    };
    std::vector<Method> methods;
    const Bvh2 bvh2 = Bvh2::build(mesh);
    {
        Method m{"bvh2", std::vector<Hit>(rays.size()), std::vector<Hit>(rays.size())};
        intersect(bvh2, rays, m.closest);
        occluded(bvh2, rays, m.any);
        methods.push_back(std::move(m));
    }
    // BVH8 on every ISA this CPU supports (the others are not compiled in or cannot run).
    const Bvh8 bvh8 = Bvh8::build(bvh2);
    for (Isa isa : supported_isas()) {
        Method m{"bvh8-" + std::string(name(isa)), std::vector<Hit>(rays.size()), std::vector<Hit>(rays.size())};
        intersect(bvh8, rays, m.closest, with_isa({}, isa));
        occluded(bvh8, rays, m.any, with_isa({}, isa));
        methods.push_back(std::move(m));
    }
    std::cout << "  ours: ";
    for (const Method& m : methods) std::cout << m.name << " ";
    std::cout << "\n";

    ReferenceCache cache;  // one reference per ray, shared by every comparison below
    const CompareOptions copts{.cache = &cache};
    for (EmbreeQuality q : {EmbreeQuality::medium, EmbreeQuality::high}) {
        for (bool robust : {false, true}) {
            const EmbreeScene embree(mesh, {q, robust, /*threads=*/1});
            const std::string ename = method_name(embree.options());
            std::vector<Hit> theirs(rays.size());
            std::vector<std::uint8_t> theirs_any(rays.size());
            embree.intersect(rays, theirs);
            embree.occluded(rays, theirs_any);
            EXPECT_EQ(embree.invalid_rays(), 0u);  // generated rays are all valid
            EXPECT_EQ(embree.unsupported_rays(), 0u);
            for (const Method& m : methods) {
                const Comparison closest = compare_methods(mesh, rays, m.closest, theirs, copts);
                report(m.name, ename, "closest", closest, rays, m.closest, theirs, strict);
                const Comparison any = compare_occluded(mesh, rays, occluded_flags(m.any), theirs_any, copts);
                report(m.name, ename, "any", any, rays, {}, {}, strict);
            }
        }
    }
}

class VsEmbree : public testing::TestWithParam<Case> {};

TEST_P(VsEmbree, NoDisagreementIsOurs) {
    const Case& c = GetParam();
    if (npm_scene(c.scene) && !workloads::is_cached(c.scene))
        GTEST_SKIP() << "scene '" << c.scene << "' is not cached in " << workloads::cache_dir().string()
                     << ": run scripts/fetch_scenes.sh (needs npm)";
    const Mesh mesh = workloads::load_scene(c.scene);
    const std::vector<Ray> rays = workloads::generate_rays(mesh, c.kind, kRays, 1 + std::uint64_t(c.kind));
    ASSERT_EQ(rays.size(), kRays);
    std::cout << c.scene << " (" << mesh.size() << " triangles), " << rays.size() << " " << workloads::name(c.kind)
              << " rays, Embree " << EmbreeScene::version() << "\n";
    run(mesh, rays, /*strict=*/false);
}

std::vector<Case> cases() {
    std::vector<Case> v;
    for (const char* s : {"bunny", "teapot", "dragon-res3", "dragon-res4", "icosphere-4"})
        for (RayKind k : {RayKind::primary, RayKind::incoherent, RayKind::diffuse}) v.push_back({s, k});
    return v;
}

INSTANTIATE_TEST_SUITE_P(Scenes, VsEmbree, testing::ValuesIn(cases()), case_name);

// The watertight family (docs/accuracy.md): a closed icosphere, rays from inside
// aimed at every vertex and every edge midpoint, also with the scene translated
// far from the origin. Every ray must hit; this is where a non-watertight test
// leaks, so Embree's default and robust modes separate here.
class VsEmbreeWatertight : public testing::TestWithParam<float> {};

TEST_P(VsEmbreeWatertight, NoDisagreementIsOurs) {
    const float offset = GetParam();
    Mesh mesh = workloads::icosphere(4);
    for (Vec3& p : mesh.positions)  // translated in double, rounded to float
        p = Vec3{float(double(p.x) + offset), float(double(p.y) + offset), float(double(p.z) + offset)};
    const Vec3 o{float(0.013 + offset), float(-0.021 + offset), float(0.034 + offset)};
    std::vector<Ray> rays;
    for (const Vec3& p : mesh.positions) rays.push_back(Ray{o, 0.0f, p - o});
    std::set<std::pair<std::uint32_t, std::uint32_t>> edges;
    for (const Triangle& t : mesh.triangles)
        for (int k = 0; k < 3; ++k) edges.insert(std::minmax(t[k], t[(k + 1) % 3]));
    for (const auto& [i, j] : edges) {
        const Vec3 a = mesh.positions[i], b = mesh.positions[j];
        const Vec3 mid{float((double(a.x) + b.x) / 2), float((double(a.y) + b.y) / 2), float((double(a.z) + b.z) / 2)};
        rays.push_back(Ray{o, 0.0f, mid - o});
    }
    std::cout << "icosphere-4 offset " << offset << ": " << mesh.size() << " triangles, " << rays.size()
              << " rays at vertices and edge midpoints from inside\n";
    run(mesh, rays, /*strict=*/true);  // watertight: we never leak, and vertex/edge rays are ties at worst
}

INSTANTIATE_TEST_SUITE_P(Offsets, VsEmbreeWatertight, testing::Values(0.0f, 1e3f),
                         [](const testing::TestParamInfo<float>& i) {
                             return i.param == 0.0f ? std::string("offset_0") : std::string("offset_1e3");
                         });

}  // namespace
}  // namespace simdbvh::reference
