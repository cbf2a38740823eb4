// SPDX-License-Identifier: MIT
// The ray families' mesh writer: binary little-endian PLY.
#include <bit>

#include "simdbvh/io/write_ply.h"
#include "simdbvh/io/output.h"

namespace simdbvh::io {

std::vector<unsigned char> encode_ply(const Mesh& mesh) {
    const std::string head = "ply\nformat binary_little_endian 1.0\ncomment simdbvh ray family\nelement vertex " +
                             std::to_string(mesh.positions.size()) +
                             "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                             std::to_string(mesh.triangles.size()) +
                             "\nproperty list uchar uint vertex_indices\nend_header\n";
    std::vector<unsigned char> bytes(head.begin(), head.end());
    bytes.reserve(head.size() + mesh.positions.size() * 12 + mesh.triangles.size() * 13);
    auto put = [&](const void* p, std::size_t n) {
        const auto* c = static_cast<const unsigned char*>(p);
        bytes.insert(bytes.end(), c, c + n);
    };
    static_assert(std::endian::native == std::endian::little);
    for (const Vec3& p : mesh.positions) put(&p, 12);
    for (const Triangle& t : mesh.triangles) {
        const unsigned char three = 3;
        put(&three, 1);
        put(t.data(), 12);
    }
    return bytes;
}

void write_ply(const std::filesystem::path& file, const Mesh& mesh) { write_file_atomic(file, encode_ply(mesh)); }

}  // namespace simdbvh::io
