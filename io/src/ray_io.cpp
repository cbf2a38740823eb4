// Ray and hit files (raw little-endian records).
#include "simdbvh/kernels/error.h"
#include "simdbvh/io/output.h"
#include "simdbvh/io/ray_files.h"
#include "records.h"

namespace simdbvh::io {
using detail::get_f32;
using detail::get_u32;
using detail::put_f32;
using detail::put_u32;
using detail::read_records;

std::vector<Ray> read_rays(const std::filesystem::path& file) {
    const auto bytes = read_records(file, sizeof(Ray), "32-byte ray");
    std::vector<Ray> rays(bytes.size() / 32);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const unsigned char* p = bytes.data() + 32 * i;
        rays[i].org = Vec3{get_f32(p), get_f32(p + 4), get_f32(p + 8)};
        rays[i].tmin = get_f32(p + 12);
        rays[i].dir = Vec3{get_f32(p + 16), get_f32(p + 20), get_f32(p + 24)};
        rays[i].tmax = get_f32(p + 28);
    }
    return rays;
}

std::vector<unsigned char> encode_rays(std::span<const Ray> rays) {
    std::vector<unsigned char> bytes(rays.size() * 32);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        unsigned char* p = bytes.data() + 32 * i;
        const Ray& r = rays[i];
        const float v[8] = {r.org.x, r.org.y, r.org.z, r.tmin, r.dir.x, r.dir.y, r.dir.z, r.tmax};
        for (int k = 0; k < 8; ++k) put_f32(p + 4 * k, v[k]);
    }
    return bytes;
}

void write_rays(const std::filesystem::path& file, std::span<const Ray> rays) {
    write_file_atomic(file, encode_rays(rays));
}

std::vector<Hit> read_hits(const std::filesystem::path& file) {
    const auto bytes = read_records(file, sizeof(Hit), "16-byte hit");
    std::vector<Hit> hits(bytes.size() / 16);
    for (std::size_t i = 0; i < hits.size(); ++i) {
        const unsigned char* p = bytes.data() + 16 * i;
        hits[i].t = get_f32(p);
        hits[i].u = get_f32(p + 4);
        hits[i].v = get_f32(p + 8);
        hits[i].prim = get_u32(p + 12);
    }
    return hits;
}

std::vector<unsigned char> encode_hits(std::span<const Hit> hits) {
    std::vector<unsigned char> bytes(hits.size() * 16);
    for (std::size_t i = 0; i < hits.size(); ++i) {
        unsigned char* p = bytes.data() + 16 * i;
        put_f32(p, hits[i].t);
        put_f32(p + 4, hits[i].u);
        put_f32(p + 8, hits[i].v);
        put_u32(p + 12, hits[i].prim);
    }
    return bytes;
}

void write_hits(const std::filesystem::path& file, std::span<const Hit> hits) {
    write_file_atomic(file, encode_hits(hits));
}

}  // namespace simdbvh::io
