// Bad input: every malformed file throws simdbvh::Error naming the file (and
// the line where known); counts are checked against the size before
// allocating; out-of-range indices name the triangle; NaN/Inf vertices give
// the count and first index; drop_invalid drops and counts.
#include <gtest/gtest.h>

#include <string>

#include "simdbvh/kernels/error.h"
#include "simdbvh/io/load.h"
#include "support/scene.h"

using simdbvh::Mesh;
using simdbvh::io::load_mesh;
using simdbvh::io::LoadOptions;
using simdbvh::io::LoadReport;

namespace {

// Loads `text` as `name` and returns the error message ("" when it loaded).
std::string error_of(const test::TempDir& dir, const std::string& name, const std::string& text, bool gz = false) {
    const auto path = dir / name;
    if (gz) test::write_gzip(path, text);
    else test::write_text(path, text);
    try {
        load_mesh(path);
    } catch (const simdbvh::Error& e) {
        return e.what();
    }
    return "";
}

#define EXPECT_ERROR(dir, name, text, ...)                                       \
    do {                                                                         \
        const std::string msg_ = error_of(dir, name, text);                      \
        EXPECT_FALSE(msg_.empty()) << "loaded without error: " << name;          \
        EXPECT_NE(msg_.find((dir / name).string()), std::string::npos) << msg_;  \
        for (const char* part : std::initializer_list<const char*>{__VA_ARGS__}) \
            EXPECT_NE(msg_.find(part), std::string::npos) << msg_;               \
    } while (0)

const std::string kPlyHead =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 1\nproperty list uchar int vertex_indices\nend_header\n";

}  // namespace

TEST(LoadErrors, MissingFileAndUnknownFormat) {
    test::TempDir dir;
    EXPECT_THROW(load_mesh(dir / "nope.ply"), simdbvh::Error);
    EXPECT_ERROR(dir, "x.3ds", "whatever", "unknown mesh format");
    EXPECT_ERROR(dir, "empty.obj", "", "empty");
    EXPECT_THROW(load_mesh(dir.path()), simdbvh::Error);
}

TEST(LoadErrors, PlyHeader) {
    test::TempDir dir;
    EXPECT_ERROR(dir, "a.ply", "plx\nformat ascii 1.0\nend_header\n", ":1:", "not a PLY");
    EXPECT_ERROR(dir, "b.ply", "ply\nformat ascii 1.0\nelement vertex 3\n", "end_header");
    EXPECT_ERROR(dir, "c.ply", "ply\nformat utf8 1.0\nend_header\n", ":2:", "format");
    EXPECT_ERROR(dir, "d.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\nend_header\n",
                 ":4:", "float128");
    EXPECT_ERROR(dir, "e.ply", "ply\nformat ascii 1.0\nelement vertex -1\nend_header\n", ":3:");
    EXPECT_ERROR(dir, "f.ply", "ply\nelement vertex 0\nend_header\n", "format");
    EXPECT_ERROR(dir, "g.ply",
                 "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n0 0\n",
                 "x, y or z");
}

TEST(LoadErrors, PlyCountsLargerThanFileBeforeAllocating) {
    test::TempDir dir;
    // 1e9 vertices (and faces) in a tiny file: an error, not a 12 GB allocation.
    const std::string big =
        "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000\nproperty float x\nproperty float y\n"
        "property float z\nelement face 1000000000\nproperty list uchar int vertex_indices\nend_header\n";
    EXPECT_ERROR(dir, "big.ply", big + std::string(1000, '\0'), ":3:", "1000000000");
    const std::string big_ascii =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 999999999999\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    EXPECT_ERROR(dir, "big_ascii.ply", big_ascii, ":7:", "999999999999");
    // Also behind gzip: the check is against the decompressed size.
    const std::string msg = error_of(dir, "big.ply.gz", big + std::string(100000, '\0'), true);
    EXPECT_NE(msg.find("1000000000"), std::string::npos) << msg;
}

TEST(LoadErrors, PlyTruncatedAndJunk) {
    test::TempDir dir;
    // Too short for the declared counts: caught by the size check, at the element's header line.
    EXPECT_ERROR(dir, "t.ply", kPlyHead + "0 0 0\n1 0 0\n", ":3:", "needs at least");
    // Long enough but a line short (blank padding): caught while reading.
    EXPECT_ERROR(dir, "t2.ply", kPlyHead + "0 0 0\n1 0 0\n0 1 0\n" + std::string(20, ' ') + "\n", "end of file",
                 "'face'");
    EXPECT_ERROR(dir, "j.ply", kPlyHead + "0 0 0\n1 0 zero\n0 1 0\n3 0 1 2\n", ":11:", "'zero'");
    EXPECT_ERROR(dir, "m.ply", kPlyHead + "0 0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", ":10:", "too many");
    EXPECT_ERROR(dir, "f.ply", kPlyHead + "0 0 0\n1 0 0\n0 1 0\n3 0 1\n", ":13:", "fewer than");
    EXPECT_ERROR(dir, "x.ply", kPlyHead + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n4 5 6\n", ":14:", "after");
    EXPECT_ERROR(dir, "n.ply", kPlyHead + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2.5\n", ":13:", "'2.5'");
    EXPECT_ERROR(dir, "o.ply", kPlyHead + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n" + std::string(3, '\0'), ":14:", "NUL byte");
    EXPECT_ERROR(dir, "h.ply", kPlyHead + "0 0 1e39\n1 0 0\n0 1 0\n3 0 1 2\n", ":10:", "1e39");
    // Binary, truncated in the middle of the face list.
    std::string bin =
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    bin += std::string(36, '\0');
    bin += std::string("\x03\x00\x00\x00\x00\x01\x00\x00\x00", 9);
    EXPECT_ERROR(dir, "tb.ply", bin, "truncated");
}

TEST(LoadErrors, TruncatedGzip) {
    test::TempDir dir;
    std::string text = kPlyHead + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    for (int i = 0; i < 200; ++i) text += "comment padding so the stream is not tiny\n";
    test::write_gzip(dir / "full.ply.gz", text);
    const std::string gz = test::read_bytes(dir / "full.ply.gz");
    test::write_text(dir / "cut.ply.gz", gz.substr(0, gz.size() / 2));
    try {
        load_mesh(dir / "cut.ply.gz");
        FAIL() << "truncated gzip loaded";
    } catch (const simdbvh::Error& e) {
        EXPECT_NE(std::string(e.what()).find("cut.ply.gz"), std::string::npos) << e.what();
    }
}

TEST(LoadErrors, OutOfRangeIndexNamesTheTriangle) {
    test::TempDir dir;
    EXPECT_ERROR(dir, "i.ply", kPlyHead + "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", ":13:", "triangle 0", "index 3",
                 "3 vertices");
    // The second triangle of a fan: triangle 1 of face 0.
    EXPECT_ERROR(dir, "i.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 3 7\n", ":5:", "triangle 2", "face 1",
                 "index 7");
    EXPECT_ERROR(dir, "z.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", ":4:", "triangle 0", "index 0");
    EXPECT_ERROR(dir, "r.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 1 2\n", ":4:", "index -4");
    EXPECT_ERROR(dir, "i.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 2 1 -1\n", ":7:", "triangle 1", "face 1");
    std::string bin =
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    bin += std::string(36, '\0');
    bin += std::string("\x03\x00\x00\x00\x00\x01\x00\x00\x00\x09\x00\x00\x00", 13);
    EXPECT_ERROR(dir, "ib.ply", bin, "triangle 0", "index 9");
}

TEST(LoadErrors, ObjJunk) {
    test::TempDir dir;
    EXPECT_ERROR(dir, "a.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0 junk\n", ":3:", "'junk'");
    EXPECT_ERROR(dir, "b.obj", "v 0 0\n", ":1:");
    EXPECT_ERROR(dir, "c.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n", ":4:", "'x'");
    EXPECT_ERROR(dir, "d.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", ":4:", "2 vertices; at least 3 needed");
    EXPECT_ERROR(dir, "e.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/a 2 3\n", ":4:");
    EXPECT_ERROR(dir, "f.obj", "v 3.1+e2 0 0\n", ":1:");
    EXPECT_ERROR(dir, "g.obj", std::string("\xFF\xFEv\0 \0", 6), "UTF-16");
}

TEST(LoadErrors, StlAndOff) {
    test::TempDir dir;
    EXPECT_ERROR(dir, "a.stl", "solid x\n facet normal 0 0 1\n outer loop\n vertex 0 0 0\n vertex 1 0 0\n",
                 "end of file");
    EXPECT_ERROR(dir, "b.stl", "solid x\n facet normal 0 0 1\n outer loop\n vertex 0 0 0\n vertex 1 O 0\n",
                 ":5:", "'O'");
    std::string bin(80, 'x');
    bin += std::string("\x10\x00\x00\x00", 4) + std::string(100, '\0');  // claims 16 triangles, has 2
    EXPECT_ERROR(dir, "c.stl", bin, "16 triangles");
    EXPECT_ERROR(dir, "d.stl", "hello", "not an STL");
    EXPECT_ERROR(dir, "a.off", "OFF\n353535235358 6 0\n0 0 0\n", ":2:", "353535235358");
    EXPECT_ERROR(dir, "b.off", "OFF\n3 4\n0.1 0.2 0.3\n0.2 0.3 0.4\n0.3 0.4 0.5\n", "end of file", "expected a face");
    EXPECT_ERROR(dir, "b2.off", "OFF\n3 1\n0 0 0\n1 0 0\n0 1 0\n" + std::string(20, ' ') + "\n", "end of file");
    EXPECT_ERROR(dir, "c.off", "NOT\n", "not an OFF");
    EXPECT_ERROR(dir, "d.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n9 9 9\n", ":7:", "after");
}

TEST(LoadErrors, NonFiniteVertexCountAndFirstIndex) {
    test::TempDir dir;
    const std::string obj = "v 0 0 0\nv nan 0 0\nv 0 1 0\nv 0 0 inf\nv 1 1 1\nf 1 2 3\nf 1 3 5\nf 4 5 1\nf 1 3 5\n";
    EXPECT_ERROR(dir, "nan.obj", obj, "2 vertices", "NaN or infinite", "first: vertex 1");
    LoadReport report;
    report.dropped_triangles = 99;
    const Mesh m = load_mesh(dir / "nan.obj", LoadOptions{.drop_invalid = true}, &report);
    EXPECT_EQ(report.dropped_triangles, 2u);
    ASSERT_EQ(m.triangles.size(), 2u);
    EXPECT_EQ(m.triangles[0], (simdbvh::Triangle{0, 2, 4}));
    EXPECT_EQ(m.triangles[1], (simdbvh::Triangle{0, 2, 4}));
    EXPECT_NO_THROW(simdbvh::validate(m));
    // All invalid: an empty mesh.
    test::write_text(dir / "all.obj", "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const Mesh e = load_mesh(dir / "all.obj", LoadOptions{.drop_invalid = true}, &report);
    EXPECT_EQ(e.triangles.size(), 0u);
    EXPECT_EQ(report.dropped_triangles, 1u);
    // A clean file reports zero.
    test::write_text(dir / "ok.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    load_mesh(dir / "ok.obj", LoadOptions{.drop_invalid = true}, &report);
    EXPECT_EQ(report.dropped_triangles, 0u);
}

TEST(LoadErrors, BinaryPlyNanVertex) {
    test::TempDir dir;
    std::string bin =
        "ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    bin += std::string(24, '\0') + std::string("\x7f\xc0\x00\x00", 4) + std::string(8, '\0');  // vertex 2: x = NaN
    bin += std::string("\x03\x00\x00\x00\x00\x00\x00\x00\x01\x00\x00\x00\x02", 13);
    EXPECT_ERROR(dir, "nan.ply", bin, "1 vertex is NaN or infinite", "first: vertex 2");
}
