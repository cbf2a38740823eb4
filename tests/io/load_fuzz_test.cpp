// Seeded mutation fuzzing of the loaders and ray/hit readers, bounded in
// iterations: every mutated file either loads (and then validates) or throws
// simdbvh::Error; nothing else (no crash, no other exception). Run it under
// ASan/UBSan too.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "simdbvh/kernels/error.h"
#include "simdbvh/io/load.h"
#include "simdbvh/io/ray_files.h"
#include "support/scene.h"

namespace {

struct SplitMix {
    std::uint64_t s;
    std::uint64_t next() {
        std::uint64_t z = (s += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    std::size_t below(std::size_t n) { return n ? std::size_t(next() % n) : 0; }
};

std::string mutate(std::string s, SplitMix& rng) {
    const int edits = 1 + int(rng.below(4));
    static const char* tokens[] = {"-1", "4294967296", "nan",  "inf",  "1e39",         "99999999999",
                                   " ",  "\n",         "\r",   "/",    "//",           "#",
                                   "0",  "3",          "\xff", "\x01", "end_header\n", "element face 1000000000\n"};
    for (int e = 0; e < edits; ++e) {
        const std::size_t at = rng.below(s.size() + 1);
        switch (rng.below(5)) {
        case 0:
            if (!s.empty()) s[rng.below(s.size())] = char(rng.next());
            break;
        case 1: s.resize(at); break;
        case 2: s.insert(at, tokens[rng.below(std::size(tokens))]); break;
        case 3:
            if (at < s.size()) s.erase(at, 1 + rng.below(8));
            break;
        case 4:
            if (!s.empty()) s.insert(at, s.substr(rng.below(s.size()), 1 + rng.below(16)));
            break;
        }
    }
    return s;
}

void fuzz(const std::string& name, const std::string& seed_text, int iterations, std::uint64_t seed) {
    test::TempDir dir(/*in_memory=*/true);
    SplitMix rng{seed};
    int loaded = 0;
    for (int i = 0; i < iterations; ++i) {
        const std::string text = mutate(seed_text, rng);
        const bool gz = rng.below(8) == 0;
        const auto path = dir / (name + (gz ? ".gz" : ""));
        if (gz) test::write_gzip(path, text);
        else test::write_text(path, text);
        try {
            const simdbvh::Mesh m = simdbvh::io::load_mesh(path, {.drop_invalid = rng.below(2) == 0});
            simdbvh::validate(m);
            ++loaded;
        } catch (const simdbvh::Error&) {
        } catch (const std::exception& e) {
            FAIL() << "iteration " << i << ": non-simdbvh exception " << e.what();
        }
    }
    ::testing::Test::RecordProperty("loaded_" + name, loaded);
}

const std::string kPly =
    "ply\nformat ascii 1.0\ncomment c\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
    "property uchar red\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n"
    "0 0 0 1\n1 0 0 2\n1 1 0 3\n0 1 0.5 4\n3 0 1 2\n4 0 1 2 3\n";

std::string binary_ply() {
    std::string s =
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property double z\nelement face 1\nproperty list uchar uint vertex_indices\nend_header\n";
    for (int v = 0; v < 3; ++v) {
        const float xy[2] = {float(v & 1), float(v >> 1)};
        const double z = 0.5;
        s.append(reinterpret_cast<const char*>(xy), 8);
        s.append(reinterpret_cast<const char*>(&z), 8);
    }
    s += '\3';
    for (std::uint32_t i = 0; i < 3; ++i) s.append(reinterpret_cast<const char*>(&i), 4);
    return s;
}

std::string binary_stl() {
    std::string s(80, 's');
    const std::uint32_t n = 2;
    s.append(reinterpret_cast<const char*>(&n), 4);
    for (int t = 0; t < 2; ++t) {
        for (int k = 0; k < 12; ++k) {
            const float f = float(k % 3 == t);
            s.append(reinterpret_cast<const char*>(&f), 4);
        }
        s += std::string(2, '\0');
    }
    return s;
}

}  // namespace

TEST(LoadFuzz, PlyAscii) { fuzz("f.ply", kPly, 1500, 1); }
TEST(LoadFuzz, PlyBinary) { fuzz("f.ply", binary_ply(), 1500, 2); }
TEST(LoadFuzz, Obj) {
    fuzz("f.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0 1\nv 0 1 0\nvt 0 0\nf 1/1/1 2/1/1 3/1/1 4/1/1\nf -1 -2 -3\n", 1500, 3);
}
TEST(LoadFuzz, StlAscii) { fuzz("f.stl", test::read_bytes(test::data_file("triangle_ascii.stl")), 1500, 4); }
TEST(LoadFuzz, StlBinary) { fuzz("f.stl", binary_stl(), 1500, 5); }
TEST(LoadFuzz, Off) { fuzz("f.off", test::read_bytes(test::data_file("tetra.off")), 1500, 6); }

TEST(LoadFuzz, RayAndHitReaders) {
    test::TempDir dir(/*in_memory=*/true);
    SplitMix rng{7};
    for (int i = 0; i < 500; ++i) {
        const std::string bytes(rng.below(200), char(rng.next()));
        test::write_text(dir / "r.bin", bytes);
        if (bytes.size() % 32 == 0) EXPECT_EQ(simdbvh::io::read_rays(dir / "r.bin").size(), bytes.size() / 32);
        else EXPECT_THROW(simdbvh::io::read_rays(dir / "r.bin"), simdbvh::Error);
        if (bytes.size() % 16 == 0) EXPECT_EQ(simdbvh::io::read_hits(dir / "r.bin").size(), bytes.size() / 16);
        else EXPECT_THROW(simdbvh::io::read_hits(dir / "r.bin"), simdbvh::Error);
    }
}
