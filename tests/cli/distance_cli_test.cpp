// simdbvh gen-points and distance: the records against the brute-force
// closest point, the file layout, and bad input (exit 2, no output, nothing
// existing destroyed).
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "simdbvh/query/closest_point.h"
#include "simdbvh/query/inside.h"
#include "simdbvh/io/output.h"
#include "simdbvh/io/point_files.h"
#include "simdbvh/workloads/scenes.h"
#include "support/cli.h"
#include "support/scene.h"

namespace fs = std::filesystem;

namespace simdbvh {
namespace {

using test::CliRun;
using test::run_cli;

class DistanceCli : public testing::Test {
protected:
    std::string path(const std::string& name) const { return (dir_ / name).string(); }
    test::TempDir dir_;
};

TEST_F(DistanceCli, RecordsMatchTheBruteForce) {
    const std::string pts = path("p.bin"), out = path("d.bin");
    CliRun g = run_cli("gen-points --scene icosphere-3 --count 2000 --seed 3 --out " + pts);
    ASSERT_EQ(g.status, 0) << g.output;
    ASSERT_EQ(fs::file_size(pts), 2000u * 12);
    CliRun d = run_cli("distance --scene icosphere-3 --points " + pts + " --out " + out + " --threads 2");
    ASSERT_EQ(d.status, 0) << d.output;
    EXPECT_NE(d.output.find("points 2000"), std::string::npos) << d.output;
    ASSERT_EQ(fs::file_size(out), 2000u * 20);
    const Mesh mesh = workloads::load_scene("icosphere-3");
    const auto points = io::read_points(pts);
    const auto recs = io::read_distances(out);
    ASSERT_EQ(points.size(), 2000u);
    ASSERT_EQ(recs.size(), 2000u);
    std::size_t inside = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const ClosestPoint want = brute_force_closest_point(mesh, points[i]);
        const PointSide side = brute_force_classify_point(mesh, points[i]);
        const float signed_want = side.side == Side::inside ? -want.distance : want.distance;
        ASSERT_NE(side.side, Side::surface) << "point " << i;
        ASSERT_EQ(recs[i].prim, want.prim) << "point " << i;
        ASSERT_EQ(std::memcmp(&recs[i].distance, &signed_want, 4), 0) << "point " << i;
        ASSERT_EQ(std::memcmp(&recs[i].point, &want.point, 12), 0) << "point " << i;
        // The unit icosphere: a point's distance is about | |p| - 1 |.
        const double r = std::sqrt(double(points[i].x) * points[i].x + double(points[i].y) * points[i].y +
                                   double(points[i].z) * points[i].z);
        ASSERT_NEAR(recs[i].distance, r - 1.0, 0.02) << "point " << i << ": negative inside";
        inside += recs[i].distance < 0;
    }
    EXPECT_GT(inside, 100u);
    EXPECT_NE(d.output.find("closed and consistently oriented"), std::string::npos) << d.output;
    // --unsigned: the same records with the sign dropped.
    CliRun u = run_cli("distance --scene icosphere-3 --points " + pts + " --out " + path("u.bin") + " --unsigned");
    ASSERT_EQ(u.status, 0) << u.output;
    const auto unsigned_recs = io::read_distances(path("u.bin"));
    for (std::size_t i = 0; i < recs.size(); ++i) ASSERT_EQ(unsigned_recs[i].distance, std::fabs(recs[i].distance));
    // Every --tree writes the same bytes as the default (bvh4, checked against brute force above).
    EXPECT_NE(d.output.find("method bvh4"), std::string::npos) << d.output;
    const std::string want_bytes = test::read_bytes(out);
    for (const char* tree : {"bvh2", "bvh8", "bvh16"}) {
        const std::string o = path(std::string(tree) + ".bin");
        CliRun t = run_cli("distance --scene icosphere-3 --points " + pts + " --out " + o + " --tree " + tree);
        ASSERT_EQ(t.status, 0) << t.output;
        EXPECT_NE(t.output.find(std::string("method ") + tree), std::string::npos) << t.output;
        EXPECT_EQ(test::read_bytes(o), want_bytes) << tree;
    }
}

TEST_F(DistanceCli, InsideWritesOneBytePerPointAndWarnsOnOpenMeshes) {
    const std::string pts = path("p.bin"), out = path("s.bin");
    // A mesh file: the unit cube, and the cube with one face removed (4 boundary edges).
    Mesh open = test::unit_cube();
    const Mesh closed = open;
    open.triangles.resize(open.triangles.size() - 2);
    std::string obj;
    for (const Vec3& v : closed.positions)
        obj += "v " + std::to_string(v.x) + " " + std::to_string(v.y) + " " + std::to_string(v.z) + "\n";
    std::string closed_obj = obj, open_obj = obj;
    for (const Triangle& t : closed.triangles)
        closed_obj +=
            "f " + std::to_string(t[0] + 1) + " " + std::to_string(t[1] + 1) + " " + std::to_string(t[2] + 1) + "\n";
    for (const Triangle& t : open.triangles)
        open_obj +=
            "f " + std::to_string(t[0] + 1) + " " + std::to_string(t[1] + 1) + " " + std::to_string(t[2] + 1) + "\n";
    test::write_text(path("cube.obj"), closed_obj);
    test::write_text(path("open.obj"), open_obj);
    const std::vector<Vec3> q = {{0.5f, 0.5f, 0.5f}, {0.5f, 0.5f, 1.5f}, {1.0f, 0.5f, 0.5f}, {0.25f, 0.75f, -1.0f}};
    io::write_file_atomic(pts, io::encode_points(q));
    CliRun r = run_cli("inside --scene " + path("cube.obj") + " --points " + pts + " --out " + out);
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("closed and consistently oriented"), std::string::npos) << r.output;
    EXPECT_EQ(test::read_bytes(out), std::string("\x01\x00\x02\x00", 4));
    const auto sides = io::read_sides(out);
    ASSERT_EQ(sides.size(), 4u);
    EXPECT_EQ(sides[2], Side::surface);
    r = run_cli("inside --scene " + path("open.obj") + " --points " + pts + " --out " + out + " --rule parity");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("warning"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("4 boundary"), std::string::npos) << r.output;
    for (const std::string& bad : {std::string("--rule majority"), std::string("--threads 0")}) {
        r = run_cli("inside --scene icosphere-3 --points " + pts + " --out " + path("x.bin") + " " + bad);
        EXPECT_EQ(r.status, 2) << bad << ": " << r.output;
        EXPECT_FALSE(fs::exists(path("x.bin")));
    }
    test::write_text(path("bad.sides"), std::string("\x00\x07", 2));
    EXPECT_THROW(io::read_sides(path("bad.sides")), Error);
}

TEST_F(DistanceCli, InsideEveryTreeWritesTheBruteForceBytes) {
    const std::string pts = path("p.bin");
    ASSERT_EQ(run_cli("gen-points --scene icosphere-3 --count 3000 --seed 5 --out " + pts).status, 0);
    const Mesh mesh = workloads::load_scene("icosphere-3");
    const auto points = io::read_points(pts);
    std::string want;
    for (const Vec3& p : points) want.push_back(char(brute_force_classify_point(mesh, p).side));
    EXPECT_GT(std::count(want.begin(), want.end(), '\x01'), 300);
    for (const char* tree : {"", "bvh2", "bvh4", "bvh8", "bvh16"}) {
        const std::string out = path(std::string("s") + tree + ".bin");
        const std::string opt = *tree ? std::string(" --tree ") + tree : std::string();
        CliRun r = run_cli("inside --scene icosphere-3 --points " + pts + " --out " + out + " --threads 2" + opt);
        ASSERT_EQ(r.status, 0) << r.output;
        EXPECT_NE(r.output.find(std::string("method ") + (*tree ? tree : "bvh8")), std::string::npos) << r.output;
        EXPECT_EQ(test::read_bytes(out), want) << (*tree ? tree : "default");
    }
    CliRun bad = run_cli("inside --scene icosphere-3 --points " + pts + " --out " + path("x.bin") + " --tree bvh32");
    EXPECT_EQ(bad.status, 2) << bad.output;
    EXPECT_FALSE(fs::exists(path("x.bin")));
}

// --ray: on an open soup the rays disagree, so the bytes say which ray ran:
// each choice writes brute force's sides for that ray (and the default is
// shortest); an unknown ray is a usage error with nothing written.
TEST_F(DistanceCli, InsideRayOptionPicksTheRayCounted) {
    const std::string pts = path("p.bin");
    ASSERT_EQ(run_cli("gen-points --scene soup-2000 --count 2000 --seed 3 --out " + pts).status, 0);
    const Mesh mesh = workloads::load_scene("soup-2000");
    const auto points = io::read_points(pts);
    std::string plus_z;
    for (const auto& [name, ray] : std::vector<std::pair<std::string, CountRay>>{
             {"", CountRay::shortest}, {"+z", CountRay::plus_z}, {"-x", CountRay::minus_x}, {"+y", CountRay::plus_y}}) {
        InsideOptions o;
        o.ray = ray;
        std::string want;
        for (const Vec3& p : points) want.push_back(char(brute_force_classify_point(mesh, p, o).side));
        const std::string out = path("s" + std::to_string(int(ray)) + ".bin");
        const std::string opt = name.empty() ? std::string() : " --ray " + name;
        CliRun r = run_cli("inside --scene soup-2000 --points " + pts + " --out " + out + opt);
        ASSERT_EQ(r.status, 0) << r.output;
        EXPECT_NE(r.output.find("ray " + (name.empty() ? std::string("shortest") : name)), std::string::npos)
            << r.output;
        EXPECT_EQ(test::read_bytes(out), want) << name;
        if (ray == CountRay::plus_z) plus_z = want;
        else EXPECT_NE(want, plus_z) << name << ": the soup should tell the rays apart";
    }
    CliRun bad = run_cli("inside --scene soup-2000 --points " + pts + " --out " + path("x.bin") + " --ray z");
    EXPECT_EQ(bad.status, 2) << bad.output;
    EXPECT_NE(bad.output.find("--ray: unknown ray 'z'"), std::string::npos) << bad.output;
    EXPECT_FALSE(fs::exists(path("x.bin")));
}

TEST_F(DistanceCli, MaxDistanceAndNonFinitePoints) {
    const std::string pts = path("p.bin"), out = path("d.bin");
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const std::vector<Vec3> p = {{0, 0, 0}, {0, 0, 1.01f}, {nan, 0, 0}, {0, 0, 3}};
    io::write_file_atomic(pts, io::encode_points(p));
    CliRun d = run_cli("distance --scene icosphere-3 --points " + pts + " --out " + out + " --max-distance 0.5");
    ASSERT_EQ(d.status, 0) << d.output;
    const auto recs = io::read_distances(out);
    ASSERT_EQ(recs.size(), 4u);
    EXPECT_EQ(recs[0].prim, kInvalidPrim) << "the centre is about 1 away, beyond 0.5";
    EXPECT_NE(recs[1].prim, kInvalidPrim);
    EXPECT_NEAR(recs[1].distance, 0.01f, 0.01f);
    for (int k : {0, 2, 3}) {
        EXPECT_EQ(recs[k].prim, kInvalidPrim) << k;
        EXPECT_TRUE(std::isinf(recs[k].distance)) << k;
    }
}

TEST_F(DistanceCli, BadInputExitsTwoAndLeavesNothing) {
    const std::string pts = path("p.bin"), out = path("d.bin"), keep = path("keep.bin");
    test::write_text(pts, std::string(100, 'x'));  // not a multiple of 12
    CliRun d = run_cli("distance --scene icosphere-3 --points " + pts + " --out " + out);
    EXPECT_EQ(d.status, 2) << d.output;
    EXPECT_NE(d.output.find(pts), std::string::npos) << d.output;
    EXPECT_NE(d.output.find("12"), std::string::npos) << d.output;
    EXPECT_FALSE(fs::exists(out));
    // An existing output survives a failed run.
    test::write_text(keep, "precious");
    d = run_cli("distance --scene icosphere-3 --points " + pts + " --out " + keep);
    EXPECT_EQ(d.status, 2);
    EXPECT_EQ(test::read_bytes(keep), "precious");
    io::write_file_atomic(pts, io::encode_points(std::vector<Vec3>{{0, 0, 0}}));
    for (const std::string& bad : {std::string("--max-distance -1"), std::string("--max-distance abc"),
                                   std::string("--threads 0"), std::string("--bogus 1"), std::string("--tree bvh32")}) {
        d = run_cli("distance --scene icosphere-3 --points " + pts + " --out " + out + " " + bad);
        EXPECT_EQ(d.status, 2) << bad << ": " << d.output;
        EXPECT_FALSE(fs::exists(out)) << bad;
    }
    d = run_cli("distance --scene icosphere-3 --points " + path("missing.bin") + " --out " + out);
    EXPECT_EQ(d.status, 2);
    EXPECT_NE(d.output.find("missing.bin"), std::string::npos) << d.output;
    d = run_cli("gen-points --scene icosphere-3 --out " + out);
    EXPECT_EQ(d.status, 2);
    EXPECT_NE(d.output.find("--count"), std::string::npos) << d.output;
    EXPECT_FALSE(fs::exists(out));
    test::write_text(path("empty.obj"), "v 0 0 0\n");
    d = run_cli("gen-points --scene " + path("empty.obj") + " --count 3 --out " + out);
    EXPECT_EQ(d.status, 2) << d.output;
    EXPECT_NE(d.output.find("empty.obj: has no triangles"), std::string::npos) << d.output;
    EXPECT_FALSE(fs::exists(out));
    d = run_cli("distance --help");
    EXPECT_EQ(d.status, 0);
    EXPECT_NE(d.output.find("--max-distance"), std::string::npos) << d.output;
}

}  // namespace
}  // namespace simdbvh
