#pragma once
// The raw ray and hit files.
#include <filesystem>
#include <span>
#include <vector>

#include "simdbvh/kernels/hit.h"
#include "simdbvh/kernels/ray.h"

namespace simdbvh::io {

// Ray file: raw little-endian records of 8 float32 (ox oy oz tmin dx dy dz tmax).
// Hit file: records of float32 t, u, v and uint32 prim. Readers check the size
// (a multiple of the record size) and throw simdbvh::Error naming the file.
// Writers go through write_file_atomic (output.h): on failure nothing is left
// behind and earlier files are untouched. encode_*: the file's bytes, for
// write_files_atomic (several outputs all or nothing).
std::vector<Ray> read_rays(const std::filesystem::path& file);
std::vector<unsigned char> encode_rays(std::span<const Ray> rays);
void write_rays(const std::filesystem::path& file, std::span<const Ray> rays);
std::vector<Hit> read_hits(const std::filesystem::path& file);
std::vector<unsigned char> encode_hits(std::span<const Hit> hits);
void write_hits(const std::filesystem::path& file, std::span<const Hit> hits);

}  // namespace simdbvh::io
