#pragma once
// Raw little-endian record files (rays, hits, points, distances): byte
// packing and a bounded, checked read of a whole file of fixed-size records.
#include <bit>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <vector>

namespace simdbvh::io::detail {

inline void put_u32(unsigned char* p, std::uint32_t v) {
    p[0] = static_cast<unsigned char>(v);
    p[1] = static_cast<unsigned char>(v >> 8);
    p[2] = static_cast<unsigned char>(v >> 16);
    p[3] = static_cast<unsigned char>(v >> 24);
}
inline std::uint32_t get_u32(const unsigned char* p) {
    return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 | std::uint32_t(p[3]) << 24;
}
inline void put_f32(unsigned char* p, float f) { put_u32(p, std::bit_cast<std::uint32_t>(f)); }
inline float get_f32(const unsigned char* p) { return std::bit_cast<float>(get_u32(p)); }

// The whole file, which must be a regular file (symlinks followed: a device
// such as /dev/zero has no size to check and would read forever) whose size is
// a multiple of `record` bytes; throws simdbvh::Error naming the file and
// `what` ("32-byte ray") otherwise.
std::vector<unsigned char> read_records(const std::filesystem::path& file, std::size_t record, const char* what);

}  // namespace simdbvh::io::detail
