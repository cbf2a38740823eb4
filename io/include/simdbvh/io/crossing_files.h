#pragma once
// Files of `trace --query count` and `trace --query all`.
// Count file: one little-endian int32 per ray, the winding sum (the signed
// crossing count; +1 per crossing leaving through a face whose normal points
// along the ray, -1 entering).
// All-hits file: 20-byte records uint32 ray index, float32 t, u, v, uint32
// prim, ordered by ray, then t, then prim.
#include <filesystem>
#include <span>
#include <vector>

#include "simdbvh/query/crossings.h"

namespace simdbvh::io {

std::vector<unsigned char> encode_counts(std::span<const CrossingCount> counts);
std::vector<std::int32_t> read_counts(const std::filesystem::path& file);

struct HitOfRay {
    std::uint32_t ray = 0;
    Hit hit;
};
std::vector<unsigned char> encode_all_hits(std::span<const AllHits> per_ray);
std::vector<HitOfRay> read_all_hits(const std::filesystem::path& file);

}  // namespace simdbvh::io
