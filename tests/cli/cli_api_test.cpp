// The CLI against the C++ API: gen-rays -> trace -> the same hits as the API;
// bad input exits 2 with a message naming the file and leaves no output.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sys/wait.h>
#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/bvh8/bvh8.h"
#include "simdbvh/workloads/rays.h"
#include "simdbvh/io/ray_files.h"
#include "support/cli.h"
#include "simdbvh/workloads/scenes.h"

namespace fs = std::filesystem;

namespace simdbvh {
namespace {

using test::CliRun;
using test::run_cli;

class Cli : public testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("simdbvh_cli_" + std::to_string(::getpid()) + "_" +
                                            testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    std::string path(const std::string& name) const { return (dir_ / name).string(); }
    fs::path dir_;
};

TEST_F(Cli, RoundTripMatchesTheApi) {
    for (const char* method : {"auto", "bvh2", "bvh4", "bvh8", "bvh16", "brute"}) {
        for (const char* kind : {"primary", "incoherent", "diffuse"}) {
            const std::string rays = path(std::string(kind) + ".bin"),
                              hits = path(std::string(method) + kind + ".hits");
            CliRun g = run_cli("gen-rays --scene icosphere-3 --kind " + std::string(kind) +
                               " --count 3000 --seed 5 --out " + rays);
            ASSERT_EQ(g.status, 0) << g.output;
            CliRun t = run_cli("trace --scene icosphere-3 --rays " + rays + " --out " + hits + " --method " + method);
            ASSERT_EQ(t.status, 0) << t.output;
            EXPECT_NE(t.output.find("isa"), std::string::npos) << "the output names the ISA";
            const Mesh mesh = workloads::load_scene("icosphere-3");
            const auto r = io::read_rays(rays);
            const auto api = workloads::generate_rays(mesh, *workloads::parse_ray_kind(kind), 3000, 5);
            ASSERT_EQ(r.size(), api.size());
            ASSERT_EQ(0, std::memcmp(r.data(), api.data(), r.size() * sizeof(Ray))) << "gen-rays differs from the API";
            const auto h = io::read_hits(hits);
            ASSERT_EQ(h.size(), r.size());
            const Bvh2 bvh = Bvh2::build(mesh);
            std::size_t n_hit = 0;
            for (std::size_t i = 0; i < r.size(); ++i) {
                ASSERT_EQ(h[i], intersect(bvh, r[i])) << method << " " << kind << " ray " << i;
                n_hit += h[i].hit();
            }
            if (std::string(kind) != "diffuse") EXPECT_GT(n_hit, r.size() / 10);  // diffuse rays leave a convex sphere
        }
    }
}

TEST_F(Cli, AnyHitAgreesOnHitOrMiss) {
    const std::string rays = path("r.bin"), a = path("a.hits"), c = path("c.hits");
    ASSERT_EQ(run_cli("gen-rays --scene soup-2000 --kind incoherent --count 2000 --out " + rays).status, 0);
    ASSERT_EQ(run_cli("trace --scene soup-2000 --rays " + rays + " --out " + c).status, 0);
    ASSERT_EQ(run_cli("trace --scene soup-2000 --rays " + rays + " --out " + a + " --any-hit --method bvh8").status, 0);
    const auto hc = io::read_hits(c), ha = io::read_hits(a);
    ASSERT_EQ(hc.size(), ha.size());
    for (std::size_t i = 0; i < hc.size(); ++i) ASSERT_EQ(hc[i].hit(), ha[i].hit()) << "ray " << i;
}

TEST_F(Cli, BadRayFileExits2WithNoOutput) {
    const std::string rays = path("bad.bin"), out = path("out.hits");
    std::ofstream(rays, std::ios::binary) << std::string(100, 'x');  // not a multiple of 32
    CliRun t = run_cli("trace --scene icosphere-2 --rays " + rays + " --out " + out);
    EXPECT_EQ(t.status, 2);
    EXPECT_NE(t.output.find(rays), std::string::npos) << t.output;
    EXPECT_NE(t.output.find("32"), std::string::npos) << t.output;
    EXPECT_FALSE(fs::exists(out));
    for (const auto& e : fs::directory_iterator(dir_)) EXPECT_EQ(e.path().string(), rays) << "stray file " << e.path();
}

TEST_F(Cli, UnknownOptionAndCommandExit2) {
    CliRun a = run_cli("trace --scene icosphere-2 --frobnicate 3");
    EXPECT_EQ(a.status, 2);
    EXPECT_NE(a.output.find("--frobnicate"), std::string::npos) << a.output;
    CliRun b = run_cli("fly");
    EXPECT_EQ(b.status, 2);
    CliRun c = run_cli("trace --scene icosphere-2 --rays x --out y --method magic");
    EXPECT_EQ(c.status, 2);
    EXPECT_NE(c.output.find("magic"), std::string::npos) << c.output;
    EXPECT_NE(c.output.find("bvh16"), std::string::npos) << "the message lists the widths: " << c.output;
    CliRun d = run_cli("trace --scene icosphere-2 --rays x --out y --method bvh32");
    EXPECT_EQ(d.status, 2);
    EXPECT_NE(d.output.find("bvh32"), std::string::npos) << d.output;
}

// --nodes quantized: the label ends in q, the hit file is byte for byte the
// full nodes' one; an unknown value, or quantized nodes for a non-wide method, exit 2.
TEST_F(Cli, QuantizedNodesSameHitFile) {
    const std::string rays = path("r.bin"), full = path("full.hits"), quant = path("q.hits"), bad = path("bad.hits");
    ASSERT_EQ(run_cli("gen-rays --scene soup-2000 --kind incoherent --count 3000 --out " + rays).status, 0);
    ASSERT_EQ(run_cli("trace --scene soup-2000 --method bvh16 --rays " + rays + " --out " + full).status, 0);
    CliRun q = run_cli("trace --scene soup-2000 --method bvh16 --nodes quantized --rays " + rays + " --out " + quant);
    ASSERT_EQ(q.status, 0) << q.output;
    EXPECT_NE(q.output.find("method bvh16q "), std::string::npos) << q.output;  // (the ISA apart: no --isa)
    std::ifstream a(full, std::ios::binary), b(quant, std::ios::binary);
    const std::string fa((std::istreambuf_iterator<char>(a)), {}), fb((std::istreambuf_iterator<char>(b)), {});
    EXPECT_GT(fa.size(), 3000u);
    EXPECT_EQ(fa, fb);
    CliRun u = run_cli("trace --scene soup-2000 --method bvh8 --nodes tiny --rays " + rays + " --out " + bad);
    EXPECT_EQ(u.status, 2);
    EXPECT_NE(u.output.find("tiny"), std::string::npos) << u.output;
    CliRun w = run_cli("trace --scene soup-2000 --method bvh2 --nodes quantized --rays " + rays + " --out " + bad);
    EXPECT_EQ(w.status, 2);
    CliRun w4 = run_cli("trace --scene soup-2000 --method bvh4 --nodes quantized --rays " + rays + " --out " + bad);
    EXPECT_EQ(w4.status, 2);
    EXPECT_NE(w4.output.find("bvh8 / bvh16"), std::string::npos) << w4.output;
    EXPECT_FALSE(fs::exists(bad));
}

// --packets and --reorder on|off|auto: primary rays (a camera's, in image
// order) give the same closest-hit file byte for byte every way; an unknown
// value, or the option for a method without it, exit 2 and write nothing.
TEST_F(Cli, PacketsAndReorderSameHitFile) {
    const std::string rays = path("p.bin"), bad = path("bad.hits");
    ASSERT_EQ(run_cli("gen-rays --scene soup-2000 --kind primary --count 4000 --out " + rays).status, 0);
    std::string first;
    for (const std::string opt : {"packets", "reorder"}) {
        for (const char* mode : {"off", "on", "auto"}) {
            const std::string out = path(opt + "_" + mode + ".hits");
            CliRun r = run_cli("trace --scene soup-2000 --method bvh8 --" + opt + " " + mode + " --rays " + rays +
                               " --out " + out);
            ASSERT_EQ(r.status, 0) << r.output;
            std::ifstream f(out, std::ios::binary);
            const std::string bytes((std::istreambuf_iterator<char>(f)), {});
            EXPECT_GT(bytes.size(), 4000u);
            if (first.empty()) first = bytes;
            else EXPECT_EQ(bytes, first) << opt << " " << mode;
        }
        CliRun u =
            run_cli("trace --scene soup-2000 --method bvh8 --" + opt + " sometimes --rays " + rays + " --out " + bad);
        EXPECT_EQ(u.status, 2);
        EXPECT_NE(u.output.find("sometimes"), std::string::npos) << u.output;
        CliRun w = run_cli("trace --scene soup-2000 --method bvh2 --" + opt + " on --rays " + rays + " --out " + bad);
        EXPECT_EQ(w.status, 2);
        EXPECT_NE(w.output.find("--" + opt), std::string::npos) << w.output;
        EXPECT_FALSE(fs::exists(bad));
    }
}

// --method bvh4|bvh8|bvh16 at every ISA the CPU has: the label names width and
// ISA, closest and any hits equal the API's BvhN<N> at that ISA.
template <int N>
void expect_width_matches_api(const std::string& rays, const std::string& hits, const std::string& any_hits, Isa isa,
                              const std::string& output) {
    const std::string label = "bvh" + std::to_string(N) + "/" + std::string(name(isa));
    EXPECT_NE(output.find("method " + label), std::string::npos) << output;
    const Mesh mesh = workloads::load_scene("soup-2000");
    const BvhN<N> bvh = BvhN<N>::build(mesh);
    const auto r = io::read_rays(rays);
    const auto h = io::read_hits(hits), a = io::read_hits(any_hits);
    ASSERT_EQ(h.size(), r.size());
    ASSERT_EQ(a.size(), r.size());
    std::vector<Hit> want(r.size()), want_any(r.size());
    intersect(bvh, r, want, with_isa({}, isa));
    occluded(bvh, r, want_any, with_isa({}, isa));
    for (std::size_t i = 0; i < r.size(); ++i) {
        ASSERT_EQ(h[i], want[i]) << label << " ray " << i;
        ASSERT_EQ(a[i], want_any[i]) << label << " any hit, ray " << i;
    }
}

TEST_F(Cli, MethodWidthsAtEveryIsa) {
    const std::string rays = path("r.bin");
    ASSERT_EQ(run_cli("gen-rays --scene soup-2000 --kind incoherent --count 2000 --seed 3 --out " + rays).status, 0);
    for (int width : {4, 8, 16})
        for (Isa isa : kAllIsas) {
            if (!supported(isa)) continue;
            const std::string m = "bvh" + std::to_string(width), i = std::string(name(isa));
            const std::string hits = path(m + i + ".hits"), any = path(m + i + ".any");
            const std::string base = "trace --scene soup-2000 --rays " + rays + " --method " + m + " --isa " + i;
            CliRun t = run_cli(base + " --out " + hits);
            ASSERT_EQ(t.status, 0) << t.output;
            CliRun u = run_cli(base + " --any-hit --out " + any);
            ASSERT_EQ(u.status, 0) << u.output;
            if (width == 4) expect_width_matches_api<4>(rays, hits, any, isa, t.output);
            if (width == 8) expect_width_matches_api<8>(rays, hits, any, isa, t.output);
            if (width == 16) expect_width_matches_api<16>(rays, hits, any, isa, t.output);
        }
}

// --method brute8 (SIMD brute force, no tree) at every ISA: the same hit
// files, byte for byte, as the scalar brute force; closest and any hit.
TEST_F(Cli, SimdBruteForceEqualsBruteForceAtEveryIsa) {
    const std::string rays = path("r.bin");
    ASSERT_EQ(run_cli("gen-rays --scene soup-2000 --kind incoherent --count 3000 --seed 4 --out " + rays).status, 0);
    const std::string base = "trace --scene soup-2000 --rays " + rays;
    for (const std::string any : {"", " --any-hit"}) {
        const std::string ref = path("brute" + std::to_string(any.size()) + ".hits");
        ASSERT_EQ(run_cli(base + " --method brute" + any + " --out " + ref).status, 0);
        const auto want = io::read_hits(ref);
        std::size_t hit = 0;
        for (const Hit& h : want) hit += h.hit();
        EXPECT_GT(hit, want.size() / 10);
        for (Isa isa : kAllIsas) {
            if (!supported(isa)) continue;
            const std::string out = path("b8" + std::string(name(isa)) + std::to_string(any.size()) + ".hits");
            CliRun t = run_cli(base + " --method brute8 --isa " + std::string(name(isa)) + " --threads 2" + any +
                               " --out " + out);
            ASSERT_EQ(t.status, 0) << t.output;
            EXPECT_NE(t.output.find("method brute8/" + std::string(name(isa))), std::string::npos) << t.output;
            const auto got = io::read_hits(out);
            ASSERT_EQ(got.size(), want.size());
            for (std::size_t i = 0; i < got.size(); ++i) {
                if (any.empty()) ASSERT_EQ(got[i], want[i]) << name(isa) << " ray " << i;
                else ASSERT_EQ(got[i].hit(), want[i].hit()) << name(isa) << " any hit, ray " << i;
            }
        }
    }
}

// info reports every width collapsed from the same BVH2: a block per width and
// one table whose nodes and depth are the API's.
TEST_F(Cli, InfoReportsEveryWidth) {
    CliRun t = run_cli("info --scene icosphere-3");
    ASSERT_EQ(t.status, 0) << t.output;
    for (const char* block : {"bvh4 (sah collapse)", "bvh8 (sah collapse)", "bvh16 (sah collapse)", "widths ("})
        EXPECT_NE(t.output.find(block), std::string::npos) << block << " missing in\n" << t.output;
    const Bvh2 bvh2 = Bvh2::build(workloads::load_scene("icosphere-3"));
    auto row = [&](const WideStats& s) {
        char buf[128];
        std::snprintf(buf, sizeof buf, "  %-6d %10zu %6d %10.1f", s.width, s.nodes, s.depth, s.bytes_per_triangle);
        return std::string(buf);
    };
    for (const std::string& r :
         {row(Bvh4::build(bvh2).stats()), row(Bvh8::build(bvh2).stats()), row(Bvh16::build(bvh2).stats())})
        EXPECT_NE(t.output.find(r), std::string::npos) << "row '" << r << "' missing in\n" << t.output;
}

TEST_F(Cli, MalformedMeshNamesTheFile) {
    const std::string mesh = path("broken.obj"), rays = path("r.bin"), out = path("o.hits");
    std::ofstream(mesh) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n";  // index out of range
    ASSERT_EQ(run_cli("gen-rays --scene icosphere-2 --kind incoherent --count 10 --out " + rays).status, 0);
    CliRun t = run_cli("trace --scene " + mesh + " --rays " + rays + " --out " + out);
    EXPECT_EQ(t.status, 2);
    EXPECT_NE(t.output.find("broken.obj"), std::string::npos) << t.output;
    EXPECT_FALSE(fs::exists(out));
    std::ofstream(mesh) << "v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    CliRun n = run_cli("info --scene " + mesh);
    EXPECT_EQ(n.status, 2);
    EXPECT_NE(n.output.find("broken.obj"), std::string::npos) << n.output;
}

TEST_F(Cli, UnsupportedIsaIsAClearError) {
    CliRun t = run_cli("info --scene icosphere-1 --isa avx9000");
    EXPECT_EQ(t.status, 2);
    EXPECT_NE(t.output.find("avx9000"), std::string::npos) << t.output;
}

}  // namespace
}  // namespace simdbvh
