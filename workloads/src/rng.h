#pragma once
// A self-contained deterministic PRNG (SplitMix64, Steele et al. 2014): the same
// seed gives the same numbers on every machine and standard library. Never use
// std:: distributions here; their output differs between implementations.
#include <cstdint>

namespace simdbvh::workloads::detail {

class Rng {
public:
    explicit Rng(std::uint64_t seed) : s_(seed) {}
    std::uint64_t next() {
        std::uint64_t z = (s_ += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    // Uniform in [0, 1): 24 random bits, exact in float.
    float uniform() { return float(next() >> 40) * 0x1p-24f; }
    // Uniform in [a, b).
    float uniform(float a, float b) { return a + (b - a) * uniform(); }
    // Uniform integer in [0, n) (n > 0), by multiply-shift.
    std::uint32_t below(std::uint32_t n) { return std::uint32_t(((next() >> 32) * std::uint64_t(n)) >> 32); }

private:
    std::uint64_t s_;
};

// Stateless hash of integers to [0, 1) (for lattice noise).
inline float hash01(std::uint64_t a, std::uint64_t b, std::uint64_t seed) {
    Rng r(seed ^ (a * 0x9E3779B97F4A7C15ull) ^ (b * 0xC2B2AE3D27D4EB4Full));
    return r.uniform();
}

}  // namespace simdbvh::workloads::detail
