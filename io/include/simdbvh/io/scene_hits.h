#pragma once
// Scene hit file: raw little-endian records of float32 t, u, v and uint32
// prim, geom, inst (24 bytes, SceneHit). A miss: t = +inf, prim, geom and inst
// 0xFFFFFFFF. Read/write like the hit file (rays.h): the reader checks the size,
// the writer is atomic.
#include <filesystem>
#include <span>
#include <vector>

#include "simdbvh/scene/scene_hit.h"

namespace simdbvh::io {

std::vector<SceneHit> read_scene_hits(const std::filesystem::path& file);
std::vector<unsigned char> encode_scene_hits(std::span<const SceneHit> hits);
void write_scene_hits(const std::filesystem::path& file, std::span<const SceneHit> hits);

}  // namespace simdbvh::io
