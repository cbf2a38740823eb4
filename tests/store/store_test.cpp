// Saved structures: a loaded tree is the saved one (every array byte for
// byte, every hit bit for bit on every ISA, mapped or read), and every kind
// of bad file is a simdbvh::Error naming the file and the problem.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <string>
#include <tuple>

#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/bvh8/bvh8.h"
#include "simdbvh/kernels/isa.h"
#include "simdbvh/store/store.h"
#include "support/rays.h"
#include "support/scene.h"

namespace simdbvh {
namespace {

using workloads::RayKind;

void write_bytes(const std::filesystem::path& f, const std::vector<unsigned char>& b) {
    std::ofstream(f, std::ios::binary).write(reinterpret_cast<const char*>(b.data()), std::streamsize(b.size()));
}
std::vector<unsigned char> bytes_of(const std::filesystem::path& f) {
    const std::string s = test::read_bytes(f);
    return {s.begin(), s.end()};
}
template <class V>
bool same_bytes(const V& a, const V& b) {
    // (memcmp of an empty vector's null data is undefined even for 0 bytes: UBSan says so)
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) == 0);
}
// Recomputes the header checksum after an edit of the header, so the check
// under test (not the checksum) is what refuses the file.
void reseal_header(std::vector<unsigned char>& b) {
    const std::uint64_t h = xxh64(std::span(b).first(504));
    std::memcpy(b.data() + 504, &h, 8);
}
void reseal(std::vector<unsigned char>& b) {
    const std::uint64_t p = xxh64(std::span(b).subspan(512));
    std::memcpy(b.data() + 64, &p, 8);
    reseal_header(b);
}

// Message names the file and says what is wrong.
#define EXPECT_LOAD_ERROR(stmt, file_, problem_)                         \
    do {                                                                 \
        try {                                                            \
            stmt;                                                        \
            ADD_FAILURE() << "no error";                                 \
        } catch (const Error& e) {                                       \
            const std::string m = e.what();                              \
            EXPECT_NE(m.find((file_).string()), std::string::npos) << m; \
            EXPECT_NE(m.find(problem_), std::string::npos) << m;         \
        }                                                                \
    } while (0)

TEST(Xxh64, MatchesTheReferenceVectors) {
    // From the reference implementation (libxxhash 0.8.1, XXH64).
    const std::string s37 = "0123456789abcdefghijklmnopqrstuvwxyz!";
    std::vector<unsigned char> r200(200);
    for (int i = 0; i < 200; ++i) r200[i] = static_cast<unsigned char>(i);
    auto h = [](std::string_view s, std::uint64_t seed = 0) {
        return xxh64({reinterpret_cast<const unsigned char*>(s.data()), s.size()}, seed);
    };
    EXPECT_EQ(h(""), 0xef46db3751d8e999ull);
    EXPECT_EQ(h("a"), 0xd24ec4f1a98c6e5bull);
    EXPECT_EQ(h("abc"), 0x44bc2cf5ad770999ull);
    EXPECT_EQ(h(s37), 0xdde9d7f125de8f22ull);
    EXPECT_EQ(xxh64(r200, 7), 0x38095d110db174ccull);
}

struct Case {
    std::string scene;
    int width;
    bool quantized;
};
class SavedWide : public ::testing::TestWithParam<std::tuple<std::string, int, bool>> {};

template <int N>
void wide_round_trip(const std::string& scene, bool quantized) {
    SIMDBVH_LOAD_OR_SKIP(mesh, scene);
    WideOptions wo;
    wo.quantized_nodes = quantized;
    const BvhN<N> built = BvhN<N>::build(mesh, {}, wo);
    test::TempDir dir;
    const auto file = dir / "tree.simdbvh";
    save(built, mesh, file);
    const auto rays = test::rays(mesh, RayKind::incoherent, 4000, /*seed=*/5);
    const auto rays2 = test::rays(mesh, RayKind::diffuse, 4000, /*seed=*/6);
    for (bool map : {true, false}) {
        const Saved<BvhN<N>> got = load_with_mesh<BvhN<N>>(file, {.map = map, .mesh = &mesh});
        const BvhN<N>& b = got.bvh;
        ASSERT_TRUE(same_bytes(b.nodes(), built.nodes()));
        ASSERT_TRUE(same_bytes(b.blocks(), built.blocks()));
        ASSERT_TRUE(same_bytes(b.qnodes(), built.qnodes()));
        EXPECT_EQ(b.qnodes().empty(), !quantized);
        EXPECT_EQ(b.options().quantized_nodes, quantized);
        EXPECT_EQ(b.stats().sah_cost, built.stats().sah_cost);
        EXPECT_EQ(b.stats().nodes, built.stats().nodes);
        EXPECT_TRUE(same_bytes(got.mesh.positions, mesh.positions));
        EXPECT_TRUE(same_bytes(got.mesh.triangles, mesh.triangles));
        for (Isa isa : kAllIsas) {
            if (!supported(isa)) continue;
            for (const auto* rs : {&rays, &rays2}) {
                std::vector<Hit> want(rs->size()), have(rs->size()), any_w(rs->size()), any_h(rs->size());
                intersect(built, std::span<const Ray>(*rs), std::span<Hit>(want), with_isa({}, isa));
                intersect(b, std::span<const Ray>(*rs), std::span<Hit>(have), with_isa({}, isa));
                occluded(built, std::span<const Ray>(*rs), std::span<Hit>(any_w), with_isa({}, isa));
                occluded(b, std::span<const Ray>(*rs), std::span<Hit>(any_h), with_isa({}, isa));
                std::size_t hits = 0;
                for (std::size_t i = 0; i < rs->size(); ++i) {
                    ASSERT_EQ(want[i], have[i]) << "ray " << i << " isa " << name(isa) << " map " << map;
                    ASSERT_EQ(any_w[i], any_h[i]) << "ray " << i << " isa " << name(isa);
                    hits += want[i].hit();
                }
                EXPECT_GT(hits, rs->size() / 50);  // the rays do hit the scene
            }
        }
    }
    // A refit of the loaded tree with its own mesh reproduces it byte for byte.
    BvhN<N> loaded = load<BvhN<N>>(file);
    loaded.refit(mesh);
    EXPECT_TRUE(same_bytes(loaded.nodes(), built.nodes()));
}

TEST_P(SavedWide, LoadedTracesBitIdenticalOnEveryIsa) {
    const auto [scene, width, quantized] = GetParam();
    if (width == 4) wide_round_trip<4>(scene, quantized);
    if (width == 8) wide_round_trip<8>(scene, quantized);
    if (width == 16) wide_round_trip<16>(scene, quantized);
}
INSTANTIATE_TEST_SUITE_P(Widths, SavedWide,
                         ::testing::Values(std::make_tuple("bunny", 4, false), std::make_tuple("bunny", 8, false),
                                           std::make_tuple("bunny", 8, true), std::make_tuple("bunny", 16, false),
                                           std::make_tuple("bunny", 16, true), std::make_tuple("dragon", 8, false),
                                           std::make_tuple("dragon", 8, true)));

TEST(SavedBvh2, LoadedTracesBitIdentical) {
    SIMDBVH_LOAD_OR_SKIP(mesh, "bunny");
    const Bvh2 built = Bvh2::build(mesh);
    test::TempDir dir;
    const auto file = dir / "b2.simdbvh";
    save(built, mesh, file);
    const auto rays = test::rays(mesh, RayKind::incoherent, 4000, 9);
    for (bool map : {true, false}) {
        const Bvh2 b = load<Bvh2>(file, {.map = map});
        ASSERT_TRUE(same_bytes(b.nodes(), built.nodes()));
        ASSERT_TRUE(same_bytes(b.prim_ids(), built.prim_ids()));
        EXPECT_EQ(b.stats().sah_cost, built.stats().sah_cost);
        std::vector<Hit> want(rays.size()), have(rays.size());
        intersect(built, std::span<const Ray>(rays), std::span<Hit>(want));
        intersect(b, std::span<const Ray>(rays), std::span<Hit>(have));
        std::size_t hits = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            ASSERT_EQ(want[i], have[i]) << "ray " << i;
            hits += want[i].hit();
        }
        EXPECT_GT(hits, rays.size() / 50);
    }
}

TEST(SavedFile, InspectReportsWhatTheFileHolds) {
    const Mesh mesh = test::unit_cube();
    const Bvh8 b = Bvh8::build(mesh, {}, {.quantized_nodes = true});
    const auto bytes = save_bytes(b, mesh);
    const SavedInfo in = inspect_bytes(bytes, "cube");
    EXPECT_EQ(in.width, 8);
    EXPECT_TRUE(in.quantized);
    EXPECT_EQ(in.triangles, 12u);
    EXPECT_EQ(in.vertices, mesh.positions.size());
    EXPECT_EQ(in.file_bytes, bytes.size());
    EXPECT_EQ(in.mesh_hash, mesh_hash(mesh));
    EXPECT_EQ(kind_name(in), "bvh8 (quantized nodes)");
    EXPECT_EQ(in.wide_stats.nodes, b.stats().nodes);
    // Every array starts on a 64-byte boundary.
    for (int i = 0; i < 5; ++i) {
        std::uint64_t off;
        std::memcpy(&off, bytes.data() + 256 + 32 * i + 8, 8);
        EXPECT_EQ(off % 64, 0u) << "section " << i;
    }
    // Saving the loaded tree gives the same bytes (nothing is lost or made up on the way).
    EXPECT_EQ(save_bytes(load_bytes<Bvh8>(bytes, "cube").bvh, mesh), bytes);
}

TEST(SavedFile, SaveRefusesAnotherMeshAndLeavesNoFile) {
    const Mesh cube = test::unit_cube();
    const Bvh8 b = Bvh8::build(cube);
    test::TempDir dir;
    EXPECT_THROW(save(b, test::one_triangle(), dir / "x.simdbvh"), Error);
    EXPECT_FALSE(std::filesystem::exists(dir / "x.simdbvh"));
    EXPECT_THROW(save(b, cube, dir.path()), Error);  // a directory
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()), {}), 0);
}

class BadFile : public ::testing::Test {
protected:
    void SetUp() override {
        mesh = test::unit_cube();
        good = save_bytes(Bvh8::build(mesh), mesh);
    }
    std::filesystem::path put(const std::vector<unsigned char>& b) {
        write_bytes(file, b);
        return file;
    }
    Mesh mesh;
    std::vector<unsigned char> good;
    test::TempDir dir;
    std::filesystem::path file = dir / "bad.simdbvh";
};

TEST_F(BadFile, TheGoodFileLoads) { EXPECT_EQ(load<Bvh8>(put(good)).stats().triangles, 12u); }

TEST_F(BadFile, Truncated) {
    for (std::size_t keep : {std::size_t(0), std::size_t(8), std::size_t(300), good.size() - 1}) {
        std::vector<unsigned char> b(good.begin(), good.begin() + std::ptrdiff_t(keep));
        for (bool map : {true, false}) {
            const char* what = keep == 0 ? "empty" : "truncated";
            EXPECT_LOAD_ERROR(load<Bvh8>(put(b), {.map = map}), file, what);
        }
    }
    auto longer = good;
    longer.push_back(0);
    EXPECT_LOAD_ERROR(load<Bvh8>(put(longer)), file, "bytes after the end");
}

TEST_F(BadFile, WrongMagic) {
    auto b = good;
    b[1] = 'X';
    EXPECT_LOAD_ERROR(load<Bvh8>(put(b)), file, "wrong magic");
    EXPECT_LOAD_ERROR(load<Bvh8>(put({'p', 'l', 'y', '\n'})), file, "wrong magic");
    EXPECT_FALSE(is_saved_file(put(b)));
    EXPECT_TRUE(is_saved_file(put(good)));
}

TEST_F(BadFile, OtherFormatVersion) {
    auto b = good;
    b[8] = 2;
    reseal_header(b);
    EXPECT_LOAD_ERROR(load<Bvh8>(put(b)), file, "format version 2, this build reads version 1");
}

TEST_F(BadFile, FlippedByteAnywhere) {
    // Every byte of the file (the cube's is a few kilobytes): header, section
    // table, padding, nodes, blocks, mesh.
    for (std::size_t i = 0; i < good.size(); ++i) {
        auto b = good;
        b[i] ^= 0x10;
        try {
            (void)load_bytes<Bvh8>(b, "cube.simdbvh");
            ADD_FAILURE() << "byte " << i << " flipped, loaded";
        } catch (const Error& e) {
            const std::string m = e.what();
            ASSERT_NE(m.find("cube.simdbvh"), std::string::npos) << m;
            if (i >= 512) {
                ASSERT_NE(m.find("checksum mismatch"), std::string::npos) << "byte " << i << ": " << m;
            }
        }
    }
    auto b = good;
    b[good.size() / 2] ^= 1;
    EXPECT_LOAD_ERROR(load<Bvh8>(put(b)), file, "checksum mismatch");
    EXPECT_LOAD_ERROR(load<Bvh8>(put(b), {.map = false}), file, "checksum mismatch");
    b = good;
    b[300] ^= 1;  // inside the header's section table
    EXPECT_LOAD_ERROR(load<Bvh8>(put(b)), file, "header checksum mismatch");
}

TEST_F(BadFile, AnotherKindOrWidth) {
    EXPECT_LOAD_ERROR(load<Bvh4>(put(good)), file, "holds a bvh8, not the bvh4 asked for");
    EXPECT_LOAD_ERROR(load<Bvh2>(put(good)), file, "holds a bvh8, not the bvh2 asked for");
    const auto q = save_bytes(Bvh16::build(mesh, {}, {.quantized_nodes = true}), mesh);
    EXPECT_LOAD_ERROR(load<Bvh8>(put(q)), file, "holds a bvh16 (quantized nodes), not the bvh8 asked for");
    const auto b2 = save_bytes(Bvh2::build(mesh), mesh);
    EXPECT_LOAD_ERROR(load<Bvh8>(put(b2)), file, "holds a bvh2, not the bvh8 asked for");
}

TEST_F(BadFile, OffsetsOutsideTheFile) {
    for (int sec = 0; sec < 5; ++sec) {
        auto b = good;
        const std::uint64_t off = (b.size() / 64 + 1000) * 64;  // aligned, past the end
        std::memcpy(b.data() + 256 + 32 * sec + 8, &off, 8);
        reseal(b);
        EXPECT_LOAD_ERROR(load<Bvh8>(put(b)), file, "lies outside the file");
    }
    auto b = good;  // a count that overflows offset + count * size
    const std::uint64_t huge = ~std::uint64_t(0) / 2;
    std::memcpy(b.data() + 256 + 16, &huge, 8);
    reseal(b);
    EXPECT_LOAD_ERROR(load<Bvh8>(put(b)), file, "lies outside the file");
}

TEST_F(BadFile, ChildOutsideTheTreeWithAValidChecksum) {
    // A crafted file (checksums recomputed): the structural check refuses it.
    auto b = good;
    std::uint64_t nodes_off;
    std::memcpy(&nodes_off, b.data() + 256 + 8, 8);
    // Node 0, slot 0 reference: make it an inner child 1000 (the cube has one node).
    const std::uint32_t ref[2] = {1000, 0};
    std::memcpy(b.data() + nodes_off + offsetof(Node8, children), ref, 8);
    reseal(b);
    EXPECT_LOAD_ERROR(load<Bvh8>(put(b)), file, "a child outside the tree");
}

TEST_F(BadFile, BuiltFromAnotherMesh) {
    Mesh moved = mesh;
    moved.positions[0].x += 0.5f;
    EXPECT_LOAD_ERROR(load<Bvh8>(put(good), {.mesh = &moved}), file, "was built from another mesh");
    const Mesh tri = test::one_triangle();
    EXPECT_LOAD_ERROR(load<Bvh8>(put(good), {.mesh = &tri}), file, "was built from another mesh (12 triangles");
    EXPECT_NO_THROW(load<Bvh8>(put(good), {.mesh = &mesh}));
}

TEST_F(BadFile, NotARegularFile) {
    EXPECT_LOAD_ERROR(load<Bvh8>(dir.path()), dir.path(), "is a directory");
    EXPECT_LOAD_ERROR(load<Bvh8>(dir / "missing.simdbvh"), dir / "missing.simdbvh", "cannot open");
}

}  // namespace
}  // namespace simdbvh
