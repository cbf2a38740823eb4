#pragma once
// Helpers for the kernel tests: a deterministic PRNG, bit comparisons, the
// ISA parameter, and SoA packing.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "simdbvh/kernels/batch.h"
#include "simdbvh/kernels/testing.h"
#include "simdbvh/kernels/isa.h"

namespace simdbvh {
// GoogleTest prints parameters through ADL: "avx2", not "1-byte object <01>".
inline void PrintTo(Isa isa, std::ostream* os) { *os << name(isa); }
}  // namespace simdbvh

namespace simdbvh::test {

// SplitMix64 (Steele, Lea, Flood 2014): fixed seeds, same stream everywhere.
class Rng {
public:
    explicit Rng(std::uint64_t seed) : s_(seed) {}
    std::uint64_t next() {
        std::uint64_t z = (s_ += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    float uniform() { return float(next() >> 40) * 0x1p-24f; }  // [0, 1)
    float range(float lo, float hi) { return lo + (hi - lo) * uniform(); }
    int below(int n) { return int(next() % std::uint64_t(n)); }
    bool chance(float p) { return uniform() < p; }
    Vec3 in_box(float lo, float hi) { return {range(lo, hi), range(lo, hi), range(lo, hi)}; }
    Vec3 direction() {  // not normalised on purpose; never all zero
        for (;;) {
            Vec3 d = in_box(-1, 1);
            if (d.x != 0 || d.y != 0 || d.z != 0) return d;
        }
    }

private:
    std::uint64_t s_;
};

inline std::uint32_t bits_of(float f) { return std::bit_cast<std::uint32_t>(f); }

inline std::string hit_str(const Hit& h) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "{t=%a u=%a v=%a prim=%u}", double(h.t), double(h.u), double(h.v), h.prim);
    return buf;
}

inline std::string isa_param_name(const testing::TestParamInfo<Isa>& info) { return std::string(name(info.param)); }

#define SIMDBVH_SKIP_IF_UNSUPPORTED(isa) \
    if (!supported(isa)) GTEST_SKIP() << "this CPU/OS lacks " << name(isa)

// Packs triangles into Tri8 blocks (last block padded with empty slots).
inline std::vector<Tri8> pack_tri8(const std::vector<kernels::Tri1>& tris) {
    std::vector<Tri8> blocks((tris.size() + 7) / 8);
    for (auto& b : blocks) b.clear();
    for (std::size_t i = 0; i < tris.size(); ++i)
        blocks[i / 8].set(int(i % 8), tris[i].v0, tris[i].v1, tris[i].v2, tris[i].prim);
    return blocks;
}

}  // namespace simdbvh::test
