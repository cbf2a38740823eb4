// Loaders on small hand-written files in every format: PLY (ASCII, binary LE
// and BE, gzip), OBJ, STL (ASCII, binary), OFF. Face order, fan triangulation,
// exact numbers.
#include <gtest/gtest.h>

#include <bit>
#include <cstring>
#include <string>
#include <vector>

#include "simdbvh/kernels/error.h"
#include "simdbvh/io/load.h"
#include "support/scene.h"

using simdbvh::Mesh;
using simdbvh::Triangle;
using simdbvh::Vec3;
using simdbvh::io::load_mesh;

namespace {

bool same_bits(Vec3 a, Vec3 b) {
    return std::bit_cast<std::uint32_t>(a.x) == std::bit_cast<std::uint32_t>(b.x) &&
           std::bit_cast<std::uint32_t>(a.y) == std::bit_cast<std::uint32_t>(b.y) &&
           std::bit_cast<std::uint32_t>(a.z) == std::bit_cast<std::uint32_t>(b.z);
}

// Appends a value in the given byte order.
template <class T>
void put(std::string& s, T v, bool big) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    if (big) std::reverse(b, b + sizeof(T));
    s.append(b, sizeof(T));
}

// A binary PLY: vertices (double x, uchar flag, float y, int z, float nx),
// faces (int count list of uint indices, plus a uchar property), and an
// extra element that must be skipped.
std::string binary_ply(bool big) {
    std::string s = "ply\nformat ";
    s += big ? "binary_big_endian" : "binary_little_endian";
    s += " 1.0\ncomment test\nobj_info made by hand\n"
         "element vertex 5\nproperty double x\nproperty uchar flag\nproperty float y\nproperty int z\nproperty float "
         "nx\n"
         "element face 2\nproperty int8 material\nproperty list int uint vertex_indices\n"
         "element edge 1\nproperty int vertex1\nproperty list uchar float junk\n"
         "end_header\n";
    const double xs[5] = {0.1, 1.0, 1.0, 0.0, -2.5e-4};
    const float ys[5] = {0.0f, 0.0f, 1.0f, 1.0f, 0.3f};
    const int zs[5] = {0, 0, 0, 0, -7};
    for (int i = 0; i < 5; ++i) {
        put<double>(s, xs[i], big);
        put<std::uint8_t>(s, 200, big);
        put<float>(s, ys[i], big);
        put<std::int32_t>(s, zs[i], big);
        put<float>(s, 9.0f, big);
    }
    put<std::int8_t>(s, -1, big);  // quad
    put<std::int32_t>(s, 4, big);
    for (std::uint32_t i : {0u, 1u, 2u, 3u}) put<std::uint32_t>(s, i, big);
    put<std::int8_t>(s, 5, big);  // triangle
    put<std::int32_t>(s, 3, big);
    for (std::uint32_t i : {4u, 0u, 2u}) put<std::uint32_t>(s, i, big);
    put<std::int32_t>(s, 1, big);  // edge
    put<std::uint8_t>(s, 2, big);
    put<float>(s, 1.0f, big);
    put<float>(s, 2.0f, big);
    return s;
}

void expect_binary_ply_mesh(const Mesh& m) {
    ASSERT_EQ(m.positions.size(), 5u);
    EXPECT_TRUE(same_bits(m.positions[0], Vec3{float(0.1), 0.0f, 0.0f}));  // double -> float
    EXPECT_TRUE(same_bits(m.positions[4], Vec3{float(-2.5e-4), 0.3f, -7.0f}));
    ASSERT_EQ(m.triangles.size(), 3u);
    EXPECT_EQ(m.triangles[0], (Triangle{0, 1, 2}));  // fan of the quad, in order
    EXPECT_EQ(m.triangles[1], (Triangle{0, 2, 3}));
    EXPECT_EQ(m.triangles[2], (Triangle{4, 0, 2}));
}

}  // namespace

TEST(LoadPly, AsciiCrlfQuadFan) {
    const Mesh m = load_mesh(test::data_file("quad_crlf.ply"));
    ASSERT_EQ(m.positions.size(), 5u);
    ASSERT_EQ(m.triangles.size(), 3u);
    EXPECT_EQ(m.triangles[0], (Triangle{0, 1, 2}));
    EXPECT_EQ(m.triangles[1], (Triangle{0, 2, 3}));
    EXPECT_EQ(m.triangles[2], (Triangle{0, 1, 4}));
    EXPECT_TRUE(same_bits(m.positions[4], Vec3{0.5f, 0.5f, 1.0f}));
}

TEST(LoadPly, AsciiPropertiesPickedByName) {
    test::TempDir dir;
    test::write_text(dir / "a.ply",
                     "ply\nformat ascii 1.0\nCreated by Blender3D 247 - www.blender.org, source file: \n"
                     "element vertex 3\nproperty uchar red\nproperty float z\nproperty double nx\nproperty float y\n"
                     "property float x\nproperty list uchar int ignored\n"
                     "element face 1\nproperty list uint8 int32 vertex_index\nproperty float quality\n"
                     "element extra 2\nproperty int a\nend_header\n"
                     "255 3 0.5 2 1 2 7 8\n0 6 -1e3 5 4 0\n1 9 .5 8 7 1 1\n"
                     "3 2 1 0 0.25\n"
                     "1\n2\n");
    const Mesh m = load_mesh(dir / "a.ply");
    ASSERT_EQ(m.positions.size(), 3u);
    EXPECT_TRUE(same_bits(m.positions[0], Vec3{1, 2, 3}));
    EXPECT_TRUE(same_bits(m.positions[1], Vec3{4, 5, 6}));
    EXPECT_TRUE(same_bits(m.positions[2], Vec3{7, 8, 9}));
    ASSERT_EQ(m.triangles.size(), 1u);
    EXPECT_EQ(m.triangles[0], (Triangle{2, 1, 0}));
}

TEST(LoadPly, BinaryLittleEndian) {
    test::TempDir dir;
    test::write_text(dir / "le.ply", binary_ply(false));
    expect_binary_ply_mesh(load_mesh(dir / "le.ply"));
}

TEST(LoadPly, BinaryBigEndian) {
    test::TempDir dir;
    test::write_text(dir / "be.ply", binary_ply(true));
    expect_binary_ply_mesh(load_mesh(dir / "be.ply"));
}

TEST(LoadPly, GzipBySuffixAndByMagic) {
    test::TempDir dir;
    test::write_gzip(dir / "be.ply.gz", binary_ply(true));
    expect_binary_ply_mesh(load_mesh(dir / "be.ply.gz"));
    // gzip data in a file without the .gz suffix is detected by its magic bytes.
    test::write_gzip(dir / "le.ply", binary_ply(false));
    expect_binary_ply_mesh(load_mesh(dir / "le.ply"));
    // A .gz name over plain data also loads.
    test::write_text(dir / "plain.ply.gz", binary_ply(false));
    expect_binary_ply_mesh(load_mesh(dir / "plain.ply.gz"));
}

TEST(LoadPly, EmptyMeshLoads) {
    test::TempDir dir;
    test::write_text(dir / "e.ply",
                     "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\n"
                     "element face 0\nproperty list uchar int vertex_indices\nend_header\n");
    const Mesh m = load_mesh(dir / "e.ply");
    EXPECT_EQ(m.positions.size(), 0u);
    EXPECT_EQ(m.triangles.size(), 0u);
}

TEST(LoadPly, NumbersEqualStrtof) {
    const char* texts[] = {"0.1",          "1e-3",           "-2.5e-4",  "3.4028234e38", "1.17549435e-38",
                           "1e-45",        "0.333333343267", "16777217", "-0",           "1.00000006",
                           "7.0064923e-46"};
    std::string ply = "ply\nformat ascii 1.0\nelement vertex " + std::to_string(std::size(texts)) +
                      "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
    for (const char* t : texts) ply += std::string(t) + " " + t + " " + t + "\n";
    test::TempDir dir;
    test::write_text(dir / "n.ply", ply);
    const Mesh m = load_mesh(dir / "n.ply");
    ASSERT_EQ(m.positions.size(), std::size(texts));
    for (std::size_t i = 0; i < std::size(texts); ++i) {
        const float want = std::strtof(texts[i], nullptr);
        EXPECT_EQ(std::bit_cast<std::uint32_t>(m.positions[i].x), std::bit_cast<std::uint32_t>(want)) << texts[i];
    }
}

TEST(LoadObj, FormsRelativeIndicesAndFan) {
    const Mesh m = load_mesh(test::data_file("square.obj"));
    ASSERT_EQ(m.positions.size(), 5u);
    ASSERT_EQ(m.triangles.size(), 3u);
    EXPECT_EQ(m.triangles[0], (Triangle{0, 1, 2}));
    EXPECT_EQ(m.triangles[1], (Triangle{0, 2, 3}));
    EXPECT_EQ(m.triangles[2], (Triangle{4, 1, 2}));
}

TEST(LoadObj, IgnoresOtherStatementsAndKeepsFaceOrder) {
    test::TempDir dir;
    test::write_text(dir / "a.obj",
                     "mtllib x.mtl\no thing\ng group\ns 1\nusemtl red\nv 0 0 0 1\nv 1 0 0 0.5 0.5 0.5\nv 0 1 0\n"
                     "v 0 0 1\nvt 0 0\nvn 0 0 1\nvp 0.5\nl 1 2\np 1\n"
                     "f 4 3 2\nf 1 2 3 # comment\nf 2/1 3/1 4/1\nf 1//1 2//1 4//1\n");
    const Mesh m = load_mesh(dir / "a.obj");
    ASSERT_EQ(m.triangles.size(), 4u);
    EXPECT_EQ(m.triangles[0], (Triangle{3, 2, 1}));
    EXPECT_EQ(m.triangles[1], (Triangle{0, 1, 2}));
    EXPECT_EQ(m.triangles[2], (Triangle{1, 2, 3}));
    EXPECT_EQ(m.triangles[3], (Triangle{0, 1, 3}));
}

TEST(LoadObj, CommentsOnlyIsEmptyMesh) {
    test::TempDir dir;
    test::write_text(dir / "e.obj", "# nothing here\n\n");
    EXPECT_EQ(load_mesh(dir / "e.obj").triangles.size(), 0u);
}

TEST(LoadStl, Ascii) {
    const Mesh m = load_mesh(test::data_file("triangle_ascii.stl"));
    ASSERT_EQ(m.triangles.size(), 1u);
    EXPECT_TRUE(same_bits(m.positions[1], Vec3{1, 0, 0}));
}

TEST(LoadStl, BinaryEvenWhenHeaderSaysSolid) {
    std::string s = "solid but actually binary";
    s.resize(80, ' ');
    put<std::uint32_t>(s, 2, false);
    for (int t = 0; t < 2; ++t) {
        for (int k = 0; k < 3; ++k) put<float>(s, 0.0f, false);  // normal
        for (int k = 0; k < 9; ++k) put<float>(s, float(t * 9 + k) + 0.25f, false);
        put<std::uint16_t>(s, 0, false);
    }
    test::TempDir dir;
    test::write_text(dir / "b.stl", s);
    const Mesh m = load_mesh(dir / "b.stl");
    ASSERT_EQ(m.triangles.size(), 2u);
    ASSERT_EQ(m.positions.size(), 6u);  // no merging
    EXPECT_EQ(m.triangles[1], (Triangle{3, 4, 5}));
    EXPECT_TRUE(same_bits(m.positions[5], Vec3{15.25f, 16.25f, 17.25f}));
    test::write_gzip(dir / "b.stl.gz", s);
    EXPECT_EQ(load_mesh(dir / "b.stl.gz").triangles.size(), 2u);
}

TEST(LoadStl, TwoSolids) {
    test::TempDir dir;
    const std::string one = test::read_bytes(test::data_file("triangle_ascii.stl"));
    test::write_text(dir / "two.stl", one + one);
    EXPECT_EQ(load_mesh(dir / "two.stl").triangles.size(), 2u);
}

TEST(LoadOff, Tetrahedron) {
    const Mesh m = load_mesh(test::data_file("tetra.off"));
    ASSERT_EQ(m.positions.size(), 4u);
    ASSERT_EQ(m.triangles.size(), 4u);
    EXPECT_EQ(m.triangles[0], (Triangle{0, 2, 1}));
    EXPECT_EQ(m.triangles[3], (Triangle{1, 2, 3}));
}

TEST(LoadOff, PolygonsAndColoursGzip) {
    test::TempDir dir;
    test::write_gzip(dir / "q.off.gz",
                     "OFF 5 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n5 0 1 2 3 4 0.5 0.5 0.5\n3 4 3 2\n");
    const Mesh m = load_mesh(dir / "q.off.gz");
    ASSERT_EQ(m.triangles.size(), 4u);
    EXPECT_EQ(m.triangles[2], (Triangle{0, 3, 4}));
    EXPECT_EQ(m.triangles[3], (Triangle{4, 3, 2}));
}

TEST(LoadAny, ExtensionIsCaseInsensitive) {
    test::TempDir dir;
    test::write_text(dir / "T.OBJ", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    EXPECT_EQ(load_mesh(dir / "T.OBJ").triangles.size(), 1u);
}
