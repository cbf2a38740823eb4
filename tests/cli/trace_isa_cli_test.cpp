// trace names the ISA that ran for its query: without --isa the wide trees
// choose per (width, query), by timing the first batch of 8192 rays or more,
// so `trace --any-hit` reports the any-hit choice (timed on its rays), not the
// closest-hit one (never timed in that process).
#include <gtest/gtest.h>

#include <string>

#include "simdbvh/kernels/isa.h"
#include "support/cli.h"
#include "support/scene.h"

namespace {

using test::CliRun;
using test::run_cli;

TEST(TraceIsa, AnyHitReportsTheAnyHitChoice) {
    if (!simdbvh::supported(simdbvh::Isa::avx2) || !simdbvh::supported(simdbvh::Isa::avx512))
        GTEST_SKIP() << "the choice is timed only between two SIMD ISAs (this CPU lacks AVX2 or AVX-512)";
    test::TempDir dir;
    const std::string big = (dir / "big.bin").string(), small = (dir / "small.bin").string(),
                      out = (dir / "h.bin").string();
    ASSERT_EQ(run_cli("gen-rays --scene icosphere-3 --kind incoherent --count 10000 --out " + big).status, 0);
    ASSERT_EQ(run_cli("gen-rays --scene icosphere-3 --kind incoherent --count 100 --out " + small).status, 0);
    const std::string env = "env -u SIMDBVH_ISA ";
    for (const char* method : {"bvh4", "bvh8", "bvh16"}) {
        const std::string trace = std::string("trace --scene icosphere-3 --method ") + method + " --out " + out;
        const CliRun any = run_cli(trace + " --any-hit --rays " + big, env);
        ASSERT_EQ(any.status, 0) << any.output;
        EXPECT_NE(any.output.find("(timed on any-hit traces)  query any"), std::string::npos) << any.output;
        const CliRun closest = run_cli(trace + " --rays " + big, env);
        EXPECT_NE(closest.output.find("(timed on closest-hit traces)  query closest"), std::string::npos)
            << closest.output;
        const CliRun few = run_cli(trace + " --any-hit --rays " + small, env);
        EXPECT_NE(few.output.find("isa avx512 (the widest detected, not timed"), std::string::npos) << few.output;
        const CliRun forced = run_cli(trace + " --any-hit --rays " + big, "SIMDBVH_ISA=avx2 ");
        EXPECT_NE(forced.output.find("isa avx2 (forced)  query any"), std::string::npos) << forced.output;
    }
}

}  // namespace
