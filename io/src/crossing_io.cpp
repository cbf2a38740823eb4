// Count and all-hits files (see simdbvh/scene/crossing_files.h).
#include "records.h"
#include "simdbvh/io/crossing_files.h"

namespace simdbvh::io {
using detail::get_f32;
using detail::get_u32;
using detail::put_f32;
using detail::put_u32;

std::vector<unsigned char> encode_counts(std::span<const CrossingCount> counts) {
    std::vector<unsigned char> bytes(counts.size() * 4);
    for (std::size_t i = 0; i < counts.size(); ++i) put_u32(bytes.data() + 4 * i, std::uint32_t(counts[i].winding));
    return bytes;
}

std::vector<std::int32_t> read_counts(const std::filesystem::path& file) {
    const auto bytes = detail::read_records(file, 4, "4-byte count");
    std::vector<std::int32_t> out(bytes.size() / 4);
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = std::int32_t(get_u32(bytes.data() + 4 * i));
    return out;
}

std::vector<unsigned char> encode_all_hits(std::span<const AllHits> per_ray) {
    std::size_t n = 0;
    for (const AllHits& a : per_ray) n += a.hits.size();
    std::vector<unsigned char> bytes(n * 20);
    unsigned char* p = bytes.data();
    for (std::size_t r = 0; r < per_ray.size(); ++r)
        for (const Crossing& c : per_ray[r].hits) {
            put_u32(p, std::uint32_t(r));
            put_f32(p + 4, c.t);
            put_f32(p + 8, c.u);
            put_f32(p + 12, c.v);
            put_u32(p + 16, c.prim);
            p += 20;
        }
    return bytes;
}

std::vector<HitOfRay> read_all_hits(const std::filesystem::path& file) {
    const auto bytes = detail::read_records(file, 20, "20-byte all-hits");
    std::vector<HitOfRay> out(bytes.size() / 20);
    for (std::size_t i = 0; i < out.size(); ++i) {
        const unsigned char* p = bytes.data() + 20 * i;
        out[i] = HitOfRay{get_u32(p), Hit{get_f32(p + 4), get_f32(p + 8), get_f32(p + 12), get_u32(p + 16)}};
    }
    return out;
}

}  // namespace simdbvh::io
