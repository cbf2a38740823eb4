// trace --query count | all through the CLI: the watertight family (origins
// inside a closed icosphere, rays aimed at vertices and edge midpoints) has
// winding +1 on every ray; all-hit records equal the library's; bad
// combinations exit 2 and write nothing.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "simdbvh/query/crossings.h"
#include "simdbvh/io/crossing_files.h"
#include "simdbvh/io/load.h"
#include "simdbvh/io/ray_files.h"
#include "support/cli.h"
#include "support/scene.h"

namespace fs = std::filesystem;

namespace simdbvh {
namespace {

using test::CliRun;
using test::run_cli;

TEST(TraceQueryCli, CountAndAllHits) {
    test::TempDir dir;
    const std::string rays = (dir / "r.bin").string(), mesh = (dir / "m.ply").string();
    CliRun g = run_cli("gen-rays --kind watertight --quick --out " + rays + " --mesh-out " + mesh);
    ASSERT_EQ(g.status, 0) << g.output;
    for (const char* method : {"bvh2", "brute"}) {
        const std::string counts = (dir / (std::string(method) + ".counts")).string();
        CliRun c = run_cli("trace --scene " + mesh + " --rays " + rays + " --out " + counts +
                           " --query count --threads 2 --method " + method);
        ASSERT_EQ(c.status, 0) << c.output;
        const auto w = io::read_counts(counts);
        ASSERT_EQ(w.size(), io::read_rays(rays).size());
        for (std::size_t i = 0; i < w.size(); ++i) ASSERT_EQ(w[i], 1) << method << " ray " << i;
    }
    const std::string all = (dir / "all.bin").string();
    CliRun a = run_cli("trace --scene " + mesh + " --rays " + rays + " --out " + all + " --query all");
    ASSERT_EQ(a.status, 0) << a.output;
    const auto recs = io::read_all_hits(all);
    const Mesh m = io::load_mesh(mesh);
    const auto r = io::read_rays(rays);
    std::size_t k = 0;
    for (std::size_t i = 0; i < r.size(); ++i)
        for (const Crossing& c : brute_force_intersect_all(m, r[i]).hits) {
            ASSERT_LT(k, recs.size());
            ASSERT_EQ(recs[k].ray, i);
            ASSERT_EQ(recs[k].hit.prim, c.prim);
            ASSERT_EQ(recs[k].hit.t, c.t);
            ++k;
        }
    EXPECT_EQ(k, recs.size());
    const std::string bad = (dir / "bad.bin").string();
    for (const std::string& opts : {std::string("--query count --method bvh8"), std::string("--query sometimes"),
                                    std::string("--query count --any-hit"), std::string("--max-hits 3"),
                                    std::string("--query all --max-hits 0"), std::string("--query count --stats")}) {
        CliRun b = run_cli("trace --scene " + mesh + " --rays " + rays + " --out " + bad + " " + opts);
        EXPECT_EQ(b.status, 2) << opts << ": " << b.output;
        EXPECT_FALSE(fs::exists(bad)) << opts;
    }
}

}  // namespace
}  // namespace simdbvh
