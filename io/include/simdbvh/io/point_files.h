#pragma once
// Query points and closest-point results on disk (random query points: simdbvh/workloads/points.h).
//
// Points file: raw little-endian float32 x y z records (12 bytes, no header).
// Distance file: 20-byte records float32 distance, uint32 prim, float32 x y z
// (the closest point); no triangle within reach: distance +inf, prim
// 0xFFFFFFFF, point 0 0 0. The distance is signed (negative inside, 0 on the
// surface) or unsigned, as the writer chose.
// Side file: one byte per point, 0 outside, 1 inside, 2 on the surface.
// Readers check the size (a multiple of the record size) and throw
// simdbvh::Error naming the file; writers go through write_file_atomic.
#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

#include "simdbvh/query/closest_point.h"
#include "simdbvh/query/inside.h"
#include "simdbvh/kernels/aabb.h"

namespace simdbvh::io {

std::vector<Vec3> read_points(const std::filesystem::path& file);
std::vector<unsigned char> encode_points(std::span<const Vec3> points);

struct DistanceRecord {
    float distance = 0;
    std::uint32_t prim = 0;
    Vec3 point;
};
std::vector<DistanceRecord> read_distances(const std::filesystem::path& file);
std::vector<unsigned char> encode_distances(std::span<const ClosestPoint> results);
std::vector<Side> read_sides(const std::filesystem::path& file);
std::vector<unsigned char> encode_sides(std::span<const PointSide> sides);

}  // namespace simdbvh::io
