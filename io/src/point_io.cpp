// Points and distance files (raw little-endian records).
#include "records.h"
#include <string>
#include "simdbvh/kernels/error.h"
#include "simdbvh/io/point_files.h"

namespace simdbvh::io {
using detail::get_f32;
using detail::get_u32;
using detail::put_f32;
using detail::put_u32;

std::vector<Vec3> read_points(const std::filesystem::path& file) {
    const auto bytes = detail::read_records(file, 12, "12-byte point");
    std::vector<Vec3> points(bytes.size() / 12);
    for (std::size_t i = 0; i < points.size(); ++i) {
        const unsigned char* p = bytes.data() + 12 * i;
        points[i] = Vec3{get_f32(p), get_f32(p + 4), get_f32(p + 8)};
    }
    return points;
}

std::vector<unsigned char> encode_points(std::span<const Vec3> points) {
    std::vector<unsigned char> bytes(points.size() * 12);
    for (std::size_t i = 0; i < points.size(); ++i)
        for (int k = 0; k < 3; ++k) put_f32(bytes.data() + 12 * i + 4 * k, points[i][k]);
    return bytes;
}

std::vector<DistanceRecord> read_distances(const std::filesystem::path& file) {
    const auto bytes = detail::read_records(file, 20, "20-byte distance");
    std::vector<DistanceRecord> out(bytes.size() / 20);
    for (std::size_t i = 0; i < out.size(); ++i) {
        const unsigned char* p = bytes.data() + 20 * i;
        out[i] = DistanceRecord{get_f32(p), get_u32(p + 4), Vec3{get_f32(p + 8), get_f32(p + 12), get_f32(p + 16)}};
    }
    return out;
}

std::vector<unsigned char> encode_distances(std::span<const ClosestPoint> results) {
    std::vector<unsigned char> bytes(results.size() * 20);
    for (std::size_t i = 0; i < results.size(); ++i) {
        unsigned char* p = bytes.data() + 20 * i;
        const ClosestPoint& c = results[i];
        put_f32(p, c.distance);
        put_u32(p + 4, c.prim);
        for (int k = 0; k < 3; ++k) put_f32(p + 8 + 4 * k, c.point[k]);
    }
    return bytes;
}

std::vector<Side> read_sides(const std::filesystem::path& file) {
    const auto bytes = detail::read_records(file, 1, "1-byte side");
    std::vector<Side> out(bytes.size());
    for (std::size_t i = 0; i < bytes.size(); ++i) {
        if (bytes[i] > 2)
            throw Error(file.string() + ": byte " + std::to_string(i) + " is " + std::to_string(bytes[i]) +
                        " (a side is 0 outside, 1 inside, 2 on the surface)");
        out[i] = Side(bytes[i]);
    }
    return out;
}

std::vector<unsigned char> encode_sides(std::span<const PointSide> sides) {
    std::vector<unsigned char> bytes(sides.size());
    for (std::size_t i = 0; i < sides.size(); ++i) bytes[i] = static_cast<unsigned char>(sides[i].side);
    return bytes;
}

}  // namespace simdbvh::io
