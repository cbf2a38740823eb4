// simdbvh classify: a hit file with one answer of each kind (right, a miss where
// the mesh is hit, a hit where it is not, another triangle, a wrong t) gets one
// count per label; bad input exits 2 naming the file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/io/ray_files.h"
#include "simdbvh/workloads/scenes.h"
#include "support/cli.h"
#include "support/scene.h"

namespace fs = std::filesystem;

namespace simdbvh {
namespace {

using test::CliRun;
using test::run_cli;

class ClassifyCli : public testing::Test {
protected:
    std::string path(const std::string& name) const { return (dir_ / name).string(); }
    test::TempDir dir_;
};

TEST_F(ClassifyCli, OneCountPerKindOfAnswer) {
    const Mesh mesh = workloads::load_scene("icosphere-2");  // the unit sphere, 320 triangles
    // Off-axis rays (no vertex or edge on their line): +z through the sphere, -z away from it.
    const Ray in{{0.13f, 0.21f, -5.0f}, 0.0f, {0.0f, 0.0f, 1.0f}};
    const Ray away{{0.13f, 0.21f, -5.0f}, 0.0f, {0.0f, 0.0f, -1.0f}};
    const Hit right = brute_force_intersect(mesh, in);  // the float brute force, not the double reference
    ASSERT_TRUE(right.hit());
    ASSERT_NEAR(right.t, 4.0f, 0.1f);
    // The exit triangle: the far side of the sphere, hit by the same line from the other end.
    const Hit exit = brute_force_intersect(mesh, Ray{{0.13f, 0.21f, 5.0f}, 0.0f, {0.0f, 0.0f, -1.0f}});
    ASSERT_TRUE(exit.hit());
    ASSERT_NE(exit.prim, right.prim);
    Hit other = right;
    other.prim = exit.prim;  // another triangle at the right t
    Hit far = right;
    far.t = 2.0f * right.t;  // the right triangle at twice the distance
    Hit phantom;
    phantom.t = 1.0f;
    phantom.prim = 0;
    const std::vector<Ray> rays{in, in, away, in, in};
    const std::vector<Hit> hits{right, Hit{}, phantom, other, far};
    io::write_rays(path("r.bin"), rays);
    io::write_hits(path("h.bin"), hits);
    const CliRun c = run_cli("classify --scene icosphere-2 --rays " + path("r.bin") + " --hits " + path("h.bin") +
                             " --threads 2 --json " + path("c.json"));
    ASSERT_EQ(c.status, 0) << c.output;
    EXPECT_NE(c.output.find("rays 5  triangles 320"), std::string::npos) << c.output;
    EXPECT_NE(c.output.find("agree=1 tie=0 leak=1 false_hit=1 wrong_triangle=1 t_error=1"), std::string::npos)
        << c.output;
    std::ifstream j(path("c.json"));
    const std::string json((std::istreambuf_iterator<char>(j)), std::istreambuf_iterator<char>());
    EXPECT_NE(json.find("\"leak\": 1"), std::string::npos) << json;
    EXPECT_NE(json.find("\"wrong_triangle\": 1"), std::string::npos) << json;
}

TEST_F(ClassifyCli, BadInputExitsTwoNamingTheFile) {
    const Ray in{{0.13f, 0.21f, -5.0f}, 0.0f, {0.0f, 0.0f, 1.0f}};
    io::write_rays(path("r.bin"), std::vector<Ray>{in, in});
    io::write_hits(path("one.bin"), std::vector<Hit>{Hit{}});
    CliRun c = run_cli("classify --scene icosphere-2 --rays " + path("r.bin") + " --hits " + path("one.bin"));
    EXPECT_EQ(c.status, 2) << c.output;
    EXPECT_NE(c.output.find("one.bin: 1 hits for 2 rays"), std::string::npos) << c.output;
    Hit bad;
    bad.t = 1.0f;
    bad.prim = 320;  // icosphere-2 has triangles 0..319
    io::write_hits(path("bad.bin"), std::vector<Hit>{bad, Hit{}});
    c = run_cli("classify --scene icosphere-2 --rays " + path("r.bin") + " --hits " + path("bad.bin") + " --json " +
                path("out.json"));
    EXPECT_EQ(c.status, 2) << c.output;
    EXPECT_NE(c.output.find("bad.bin: hit 0 names triangle 320 of 320"), std::string::npos) << c.output;
    EXPECT_FALSE(fs::exists(path("out.json")));
    c = run_cli("classify --scene icosphere-2 --rays " + path("r.bin"));
    EXPECT_EQ(c.status, 2) << c.output;
    EXPECT_NE(c.output.find("--hits"), std::string::npos) << c.output;
}

}  // namespace
}  // namespace simdbvh
