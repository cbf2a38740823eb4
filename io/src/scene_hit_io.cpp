// Scene hit files (24-byte records, scene_hits.h).
#include "simdbvh/io/output.h"
#include "simdbvh/io/scene_hits.h"
#include "records.h"

namespace simdbvh::io {

std::vector<SceneHit> read_scene_hits(const std::filesystem::path& file) {
    const auto bytes = detail::read_records(file, sizeof(SceneHit), "24-byte scene hit");
    std::vector<SceneHit> hits(bytes.size() / 24);
    for (std::size_t i = 0; i < hits.size(); ++i) {
        const unsigned char* p = bytes.data() + 24 * i;
        hits[i] = SceneHit{detail::get_f32(p),      detail::get_f32(p + 4),  detail::get_f32(p + 8),
                           detail::get_u32(p + 12), detail::get_u32(p + 16), detail::get_u32(p + 20)};
    }
    return hits;
}

std::vector<unsigned char> encode_scene_hits(std::span<const SceneHit> hits) {
    std::vector<unsigned char> bytes(hits.size() * 24);
    for (std::size_t i = 0; i < hits.size(); ++i) {
        unsigned char* p = bytes.data() + 24 * i;
        detail::put_f32(p, hits[i].t);
        detail::put_f32(p + 4, hits[i].u);
        detail::put_f32(p + 8, hits[i].v);
        detail::put_u32(p + 12, hits[i].prim);
        detail::put_u32(p + 16, hits[i].geom);
        detail::put_u32(p + 20, hits[i].inst);
    }
    return bytes;
}

void write_scene_hits(const std::filesystem::path& file, std::span<const SceneHit> hits) {
    write_file_atomic(file, encode_scene_hits(hits));
}

}  // namespace simdbvh::io
