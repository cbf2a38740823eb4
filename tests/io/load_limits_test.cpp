// The loaders' limits (docs/cli.md#bad-input): reads bounded by what the
// header declares, non-regular files refused, gzip trailing data, counts
// checked before reserving, 32-bit index overflow, clear messages (BOM, short
// faces, 1e300).
#include <gtest/gtest.h>
#include <unistd.h>
#include <zlib.h>

#include <sys/resource.h>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "simdbvh/kernels/error.h"
#include "simdbvh/io/load.h"
#include "simdbvh/io/ray_files.h"
#include "simdbvh/workloads/scenes.h"
#include "support/scene.h"

using simdbvh::io::load_mesh;

namespace {

std::string error_of(const std::filesystem::path& path) {
    try {
        load_mesh(path);
    } catch (const simdbvh::Error& e) {
        return e.what();
    }
    return "";
}

// One gzip member of `bytes` (level 9).
std::string gzip(const std::string& bytes) {
    z_stream zs{};
    EXPECT_EQ(deflateInit2(&zs, 9, Z_DEFLATED, 15 + 16, 9, Z_DEFAULT_STRATEGY), Z_OK);
    std::string out(deflateBound(&zs, uLong(bytes.size())), '\0');
    zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data()));
    zs.avail_in = unsigned(bytes.size());
    zs.next_out = reinterpret_cast<Bytef*>(out.data());
    zs.avail_out = unsigned(out.size());
    EXPECT_EQ(deflate(&zs, Z_FINISH), Z_STREAM_END);
    out.resize(zs.total_out);
    deflateEnd(&zs);
    return out;
}

// A gzip bomb: `members` members of 64 MiB of `fill` each (legal multi-member gzip).
void write_bomb(const std::filesystem::path& file, const std::string& head, int members, char fill = '\0') {
    const std::string member = gzip(std::string(std::size_t(64) << 20, fill));
    std::ofstream out(file, std::ios::binary);
    out << gzip(head);
    for (int i = 0; i < members; ++i) out << member;
}

// Growth of the process's peak resident set (MiB) while loading `file` fails:
// a bomb read to the end would decompress 1 GiB (and peak at twice that).
// Memory, not time, is the promise: "bounded by what the input declares".
double peak_mib_to_fail(const std::filesystem::path& file, std::string& msg) {
    rusage before{};
    getrusage(RUSAGE_SELF, &before);
    msg = error_of(file);
    rusage after{};
    getrusage(RUSAGE_SELF, &after);
    return double(after.ru_maxrss - before.ru_maxrss) / 1024.0;
}

const std::string kPlyHead =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
const std::string kPlyBody = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";

std::string binary_ply_head(const std::string& coord, std::uint64_t faces) {
    return "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty " + coord + " x\nproperty " + coord +
           " y\nproperty " + coord + " z\nelement face " + std::to_string(faces) +
           "\nproperty list uchar int vertex_indices\nend_header\n";
}

}  // namespace

// A zero-filled .ply.gz (1 GiB decompressed) fails at its first line, fast.
TEST(LoadLimits, ZeroFilledPlyGzFailsFastAtTheMagic) {
    test::TempDir dir;
    const auto file = dir / "zeros.ply.gz";
    write_bomb(file, std::string(), 16);
    std::string msg;
    EXPECT_LT(peak_mib_to_fail(file, msg), 256.0);
    EXPECT_NE(msg.find(file.string()), std::string::npos) << msg;
    EXPECT_NE(msg.find("not a PLY file"), std::string::npos) << msg;
}

// The same for every format (text formats: NUL; binary STL: its header's size).
TEST(LoadLimits, ZeroFilledBombsOfEveryFormatFailFast) {
    test::TempDir dir;
    for (const char* name : {"z.obj.gz", "z.off.gz", "z.stl.gz"}) {
        write_bomb(dir / name, std::string(), 16);
        std::string msg;
        EXPECT_LT(peak_mib_to_fail(dir / name, msg), 256.0) << name;
        EXPECT_NE(msg.find((dir / name).string()), std::string::npos) << msg;
    }
}

// A valid binary PLY header followed by far more data than its counts allow.
TEST(LoadLimits, DataBeyondWhatTheHeaderDeclaresStopsEarly) {
    test::TempDir dir;
    const auto file = dir / "big.ply.gz";
    write_bomb(file, binary_ply_head("float", 1), 16);
    std::string msg;
    EXPECT_LT(peak_mib_to_fail(file, msg), 256.0);
    EXPECT_NE(msg.find("header's element counts allow"), std::string::npos) << msg;
}

// Devices are refused (a symlink to /dev/zero read forever); a symlink to a file is fine.
TEST(LoadLimits, NonRegularFilesAreRefusedSymlinksToFilesAreFine) {
    test::TempDir dir;
    std::filesystem::create_symlink("/dev/zero", dir / "zero.ply");
    const std::string msg = error_of(dir / "zero.ply");
    EXPECT_NE(msg.find("zero.ply"), std::string::npos) << msg;
    EXPECT_NE(msg.find("not a regular file"), std::string::npos) << msg;
    test::write_text(dir / "real.ply", kPlyHead + kPlyBody);
    std::filesystem::create_symlink(dir / "real.ply", dir / "link.ply");
    EXPECT_EQ(load_mesh(dir / "link.ply").size(), 1u);
}

// Garbage after the gzip stream is an error; concatenated members are legal gzip.
TEST(LoadLimits, GzipTrailingDataRejectedMembersAccepted) {
    test::TempDir dir;
    const std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    std::ofstream(dir / "junk.obj.gz", std::ios::binary) << gzip(obj) << "garbage";
    const std::string msg = error_of(dir / "junk.obj.gz");
    EXPECT_NE(msg.find("junk.obj.gz"), std::string::npos) << msg;
    EXPECT_NE(msg.find("trailing data after the gzip stream"), std::string::npos) << msg;
    std::ofstream(dir / "two.obj.gz", std::ios::binary) << gzip(obj) << gzip("f 3 2 1\n");
    EXPECT_EQ(load_mesh(dir / "two.obj.gz").size(), 2u);
}

// A face needs at least 3 indices, so 1e6 faces cannot fit in ~1 MB (was: 1 byte each, then reserve).
TEST(LoadLimits, PlyFaceCountCheckedWithThreeIndicesPerFace) {
    test::TempDir dir;
    std::string ply = binary_ply_head("float", 1000000) + std::string(36 + 1000000, '\0');
    test::write_text(dir / "faces.ply", ply);
    const std::string msg = error_of(dir / "faces.ply");
    EXPECT_NE(msg.find("count 1000000 needs at least 13 bytes"), std::string::npos) << msg;
}

// 3 n vertex indices must fit uint32; rejected before allocating.
TEST(LoadLimits, SoupTooLargeForIndicesRejectedBeforeAllocating) {
    const std::size_t n = 0xFFFFFFFFull / 3 + 1;
    try {
        simdbvh::workloads::random_soup(n, 1);
        FAIL() << "accepted";
    } catch (const simdbvh::Error& e) {
        EXPECT_NE(std::string(e.what()).find("32-bit"), std::string::npos) << e.what();
    }
    EXPECT_THROW(simdbvh::workloads::load_scene("soup-" + std::to_string(n)), simdbvh::Error);
}

TEST(LoadLimits, BinaryStlTooLargeForIndicesRejectedFromTheHeader) {
    test::TempDir dir;
    const std::uint64_t n = 0xFFFFFFFFull / 3 + 1;
    std::string head(80, ' ');
    for (int k = 0; k < 4; ++k) head += char((n >> (8 * k)) & 0xff);
    test::write_text(dir / "huge.stl", head);
    std::filesystem::resize_file(dir / "huge.stl", 84 + 50 * n);  // sparse: 71 GB that are never read
    const std::string msg = error_of(dir / "huge.stl");
    EXPECT_NE(msg.find(std::to_string(n) + " triangles"), std::string::npos) << msg;
    EXPECT_NE(msg.find("32-bit"), std::string::npos) << msg;
}

// /dev/zero as a ray file is refused (it was read as 0 rays).
TEST(LoadLimits, RayFileMustBeARegularFile) {
    try {
        simdbvh::io::read_rays("/dev/zero");
        FAIL() << "read /dev/zero as rays";
    } catch (const simdbvh::Error& e) {
        EXPECT_NE(std::string(e.what()).find("/dev/zero: is not a regular file"), std::string::npos) << e.what();
    }
}

// A UTF-8 BOM is accepted on PLY and ASCII STL, as on OBJ and OFF.
TEST(LoadLimits, Utf8BomAcceptedOnPlyAndAsciiStl) {
    test::TempDir dir;
    const std::string bom = "\xEF\xBB\xBF";
    test::write_text(dir / "bom.ply", bom + kPlyHead + kPlyBody);
    EXPECT_EQ(load_mesh(dir / "bom.ply").size(), 1u);
    test::write_text(dir / "bom.stl", bom +
                                          "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                                          "vertex 0 1 0\nendloop\nendfacet\nendsolid s\n");
    EXPECT_EQ(load_mesh(dir / "bom.stl").size(), 1u);
}

TEST(LoadLimits, OffShortFaceNamesTheFaceAndLine) {
    test::TempDir dir;
    test::write_text(dir / "short.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n");
    const std::string msg = error_of(dir / "short.off");
    EXPECT_NE(msg.find(":6: face 0 has 2 vertices; at least 3 needed"), std::string::npos) << msg;
}

TEST(LoadLimits, FiniteButHugeCoordinateIsOutOfFloatRange) {
    test::TempDir dir;
    std::string ply = binary_ply_head("double", 1);
    const double v[9] = {0, 0, 0, 1e300, 0, 0, 0, 1, 0};
    ply.append(reinterpret_cast<const char*>(v), sizeof v);
    ply += std::string("\x03\x00\x00\x00\x00\x01\x00\x00\x00\x02\x00\x00\x00", 13);
    test::write_text(dir / "huge.ply", ply);
    std::string msg = error_of(dir / "huge.ply");
    EXPECT_NE(msg.find("out of float range"), std::string::npos) << msg;
    EXPECT_EQ(msg.find("NaN"), std::string::npos) << msg;
    test::write_text(dir / "huge.obj", "v 0 0 0\nv 1e300 0 0\nv 0 1 0\nf 1 2 3\n");
    msg = error_of(dir / "huge.obj");
    EXPECT_NE(msg.find(":2: number '1e300' is out of float range"), std::string::npos) << msg;
}
