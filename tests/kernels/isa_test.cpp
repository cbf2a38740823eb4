// ISA detection, SIMDBVH_ISA parsing, and proof that a forced ISA really ran.
#include <cstdlib>
#include <string>

#include "kernel_test_util.h"
#include "simdbvh/kernels/error.h"

namespace simdbvh {
namespace {

TEST(Isa, NamesRoundTrip) {
    for (Isa isa : kAllIsas) EXPECT_EQ(parse_isa(name(isa)), isa);
    EXPECT_FALSE(parse_isa("AVX2").has_value());
    EXPECT_FALSE(parse_isa("sse").has_value());
    EXPECT_FALSE(parse_isa("").has_value());
}

TEST(Isa, ScalarAlwaysSupportedAndHierarchy) {
    EXPECT_TRUE(supported(Isa::scalar));
    if (supported(Isa::avx512)) {
        EXPECT_TRUE(supported(Isa::avx2));
    }
    EXPECT_TRUE(supported(detected_isa()));
    EXPECT_EQ(supported_isas().back(), detected_isa());
    std::cout << "CPU: " << cpu_name() << ", detected " << name(detected_isa()) << "\n";
    EXPECT_FALSE(cpu_name().empty());
}

TEST(Isa, RequestParsing) {
    EXPECT_EQ(isa_from_request(""), detected_isa());
    EXPECT_EQ(isa_from_request("scalar"), Isa::scalar);
    for (Isa isa : supported_isas()) EXPECT_EQ(isa_from_request(name(isa)), isa);
    EXPECT_THROW(isa_from_request("avx3"), Error);
    EXPECT_THROW(isa_from_request("AVX2"), Error);
    EXPECT_THROW(isa_from_request(" avx2"), Error);
    // An ISA the (given) CPU lacks is an error with a clear message, never SIGILL.
    const Isa only_scalar[] = {Isa::scalar};
    EXPECT_EQ(isa_from_request("", only_scalar), Isa::scalar);
    try {
        isa_from_request("avx512", only_scalar);
        FAIL() << "expected simdbvh::Error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("avx512"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("lacks"), std::string::npos) << e.what();
    }
    try {
        isa_from_request("neon");
        FAIL() << "expected simdbvh::Error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("neon"), std::string::npos) << e.what();
    }
}

TEST(Isa, UnsupportedIsaThrows) {
    bool any = false;
    for (Isa isa : kAllIsas) {
        if (supported(isa)) continue;
        any = true;
        EXPECT_THROW(require(isa), Error);
        EXPECT_THROW(set_active_isa(isa), Error);
        EXPECT_THROW(isa_from_request(name(isa)), Error);
        std::vector<Ray> rays(1);
        std::vector<Hit> hits(1);
        EXPECT_THROW(kernels::intersect_tri8(rays, {}, TriangleTest::watertight, hits, isa), Error);
    }
    if (!any) GTEST_SKIP() << "this CPU supports every ISA (the given-set form is tested in RequestParsing)";
}

TEST(Isa, InvalidEnumThrows) { EXPECT_THROW(require(static_cast<Isa>(7)), Error); }

class IsaRuns : public testing::TestWithParam<Isa> {};

// The per-ISA translation unit itself reports that it ran.
TEST_P(IsaRuns, ForcedIsaReallyRan) {
    const Isa isa = GetParam();
    SIMDBVH_SKIP_IF_UNSUPPORTED(isa);
    EXPECT_EQ(kernels::compiled_isa(isa), isa);
    std::vector<Ray> rays(3, Ray{{0, 0, -1}, 0, {0, 0, 1}, 10});
    std::vector<Hit> hits(3);
    std::vector<Tri8> blocks(1);
    blocks[0].clear();
    blocks[0].set(0, {-1, -1, 0}, {1, -1, 0}, {0, 1, 0}, 5);
    kernels::intersect_tri8(rays, blocks, TriangleTest::watertight, hits, isa);
    EXPECT_EQ(kernels::last_isa_used(), isa);
    EXPECT_EQ(hits[0].prim, 5u);
    Box8 box;
    box.clear();
    std::vector<std::uint8_t> masks(3);
    std::vector<float> entries(24);
    kernels::intersect_box8(rays, box, masks, entries, Isa::scalar);
    EXPECT_EQ(kernels::last_isa_used(), Isa::scalar);
    kernels::intersect_box8(rays, box, masks, entries, isa);
    EXPECT_EQ(kernels::last_isa_used(), isa);
    EXPECT_EQ(kernels::count_box8_hits(rays, {&box, 1}, isa), 0u);
    EXPECT_EQ(kernels::last_isa_used(), isa);
    std::vector<std::uint8_t> occ(3);
    kernels::occluded_tri8(rays, blocks, TriangleTest::moller, occ, {}, isa);
    EXPECT_EQ(kernels::last_isa_used(), isa);
    EXPECT_EQ(occ[2], 1);
}

TEST_P(IsaRuns, SetActiveIsaIsTheDefault) {
    const Isa isa = GetParam();
    SIMDBVH_SKIP_IF_UNSUPPORTED(isa);
    const Isa before = active_isa();
    set_active_isa(isa);
    EXPECT_EQ(active_isa(), isa);
    std::vector<Ray> rays(1, Ray{{0, 0, -1}, 0, {0, 0, 1}, 10});
    std::vector<Hit> hits(1);
    kernels::intersect_tri8(rays, {}, TriangleTest::watertight, hits);
    EXPECT_EQ(kernels::last_isa_used(), isa);
    EXPECT_FALSE(hits[0].hit());
    set_active_isa(before);
}

INSTANTIATE_TEST_SUITE_P(AllIsas, IsaRuns, testing::ValuesIn(kAllIsas), test::isa_param_name);

// Run by ctest with SIMDBVH_ISA=<value> and SIMDBVH_EXPECT_ISA=<isa>|error.
TEST(IsaEnv, EnvironmentSelectsTheImplementation) {
    const char* expect = std::getenv("SIMDBVH_EXPECT_ISA");
    if (!expect) GTEST_SKIP() << "run by ctest with SIMDBVH_ISA and SIMDBVH_EXPECT_ISA set";
    std::vector<Ray> rays(1, Ray{{0, 0, -1}, 0, {0, 0, 1}, 10});
    std::vector<Hit> hits(1);
    if (std::string(expect) == "error") {
        EXPECT_THROW(active_isa(), Error);
        EXPECT_THROW(kernels::intersect_tri8(rays, {}, TriangleTest::watertight, hits), Error);
        return;
    }
    const Isa want = *parse_isa(expect);
    if (!supported(want)) {
        EXPECT_THROW(active_isa(), Error);  // forcing a missing ISA is an error, not SIGILL
        GTEST_SKIP() << "this CPU/OS lacks " << expect << " (checked that forcing it throws)";
    }
    EXPECT_EQ(active_isa(), want);
    kernels::intersect_tri8(rays, {}, TriangleTest::watertight, hits);  // default ISA argument
    EXPECT_EQ(kernels::last_isa_used(), want);
}

}  // namespace
}  // namespace simdbvh
