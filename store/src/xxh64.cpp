// XXH64 (Yann Collet's xxHash, 64-bit variant): four independent multiply-
// rotate lanes over 32-byte stripes, about 8 bytes per cycle, so a load's
// checksum pass costs little more than reading the bytes once.
#include <bit>
#include <cstring>

#include "simdbvh/store/store.h"

namespace simdbvh {
namespace {

constexpr std::uint64_t P1 = 0x9E3779B185EBCA87ull;
constexpr std::uint64_t P2 = 0xC2B2AE3D27D4EB4Full;
constexpr std::uint64_t P3 = 0x165667B19E3779F9ull;
constexpr std::uint64_t P4 = 0x85EBCA77C2B2AE63ull;
constexpr std::uint64_t P5 = 0x27D4EB2F165667C5ull;

std::uint64_t read64(const unsigned char* p) {
    std::uint64_t v;
    std::memcpy(&v, p, 8);
    return v;
}
std::uint32_t read32(const unsigned char* p) {
    std::uint32_t v;
    std::memcpy(&v, p, 4);
    return v;
}
std::uint64_t round(std::uint64_t acc, std::uint64_t in) {
    acc += in * P2;
    acc = std::rotl(acc, 31);
    return acc * P1;
}
std::uint64_t merge(std::uint64_t acc, std::uint64_t v) {
    acc ^= round(0, v);
    return acc * P1 + P4;
}

}  // namespace

std::uint64_t xxh64(std::span<const unsigned char> bytes, std::uint64_t seed) {
    const unsigned char* p = bytes.data();
    const unsigned char* const end = p + bytes.size();
    std::uint64_t h;
    if (bytes.size() >= 32) {
        std::uint64_t v1 = seed + P1 + P2, v2 = seed + P2, v3 = seed, v4 = seed - P1;
        const unsigned char* const limit = end - 32;
        do {
            v1 = round(v1, read64(p));
            v2 = round(v2, read64(p + 8));
            v3 = round(v3, read64(p + 16));
            v4 = round(v4, read64(p + 24));
            p += 32;
        } while (p <= limit);
        h = std::rotl(v1, 1) + std::rotl(v2, 7) + std::rotl(v3, 12) + std::rotl(v4, 18);
        h = merge(h, v1);
        h = merge(h, v2);
        h = merge(h, v3);
        h = merge(h, v4);
    } else {
        h = seed + P5;
    }
    h += std::uint64_t(bytes.size());
    for (; p + 8 <= end; p += 8) {
        h ^= round(0, read64(p));
        h = std::rotl(h, 27) * P1 + P4;
    }
    if (p + 4 <= end) {
        h ^= std::uint64_t(read32(p)) * P1;
        h = std::rotl(h, 23) * P2 + P3;
        p += 4;
    }
    for (; p < end; ++p) {
        h ^= std::uint64_t(*p) * P5;
        h = std::rotl(h, 11) * P1;
    }
    h ^= h >> 33;
    h *= P2;
    h ^= h >> 29;
    h *= P3;
    h ^= h >> 32;
    return h;
}

std::uint64_t mesh_hash(const Mesh& mesh) {
    const auto pos = std::as_bytes(std::span(mesh.positions));
    const auto tri = std::as_bytes(std::span(mesh.triangles));
    const std::uint64_t h = xxh64({reinterpret_cast<const unsigned char*>(pos.data()), pos.size()}, 0);
    return xxh64({reinterpret_cast<const unsigned char*>(tri.data()), tri.size()}, h);
}

}  // namespace simdbvh
