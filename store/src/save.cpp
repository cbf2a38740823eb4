// save_bytes / save: the header, then each array at the next 64-byte
// boundary (zero padding), then the checksums (docs/saved_format.md).
#include <algorithm>

#include "format.h"
#include "simdbvh/io/output.h"
#include "simdbvh/store/store.h"

namespace simdbvh {
namespace store::detail {

const char* section_name(Section s) {
    switch (s) {
    case Section::positions: return "positions";
    case Section::triangles: return "triangles";
    case Section::wide_nodes: return "nodes";
    case Section::blocks: return "triangle blocks";
    case Section::qnodes: return "quantized nodes";
    case Section::bvh2_nodes: return "bvh2 nodes";
    case Section::prim_ids: return "triangle ids";
    case Section::gathered: return "gathered triangles";
    }
    return "unknown";
}

namespace {

struct Part {
    Section id;
    std::uint32_t elem;
    const void* data;
    std::uint64_t count;
};
template <class V>
Part part(Section id, const V& v) {
    return {id, std::uint32_t(sizeof(typename V::value_type)), v.data(), std::uint64_t(v.size())};
}

void put_build(unsigned char* h, const BuildOptions& o) {
    put<std::uint32_t>(h, kOffBuild + 0, std::uint32_t(o.builder));
    put<std::int32_t>(h, kOffBuild + 4, o.bins);
    put<std::int32_t>(h, kOffBuild + 8, o.max_leaf_size);
    put<std::int32_t>(h, kOffBuild + 12, o.min_leaf_size);
    put<float>(h, kOffBuild + 16, o.traversal_cost);
    put<float>(h, kOffBuild + 20, o.intersection_cost);
    put<std::int32_t>(h, kOffBuild + 24, o.max_depth);
    put<std::int32_t>(h, kOffBuild + 28, o.threads);
}
void put_bounds(unsigned char* h, const Aabb& b) {
    const float f[6] = {b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y, b.hi.z};
    for (int i = 0; i < 6; ++i) put<float>(h, kOffBounds + 4 * i, f[i]);
}

// Lays out the parts, copies them and fills the common header fields; the
// caller has written the kind-specific ones into `head` (kHeaderBytes).
std::vector<unsigned char> assemble(const unsigned char* head, int width, bool quantized, const Mesh& mesh,
                                    std::span<const Part> parts) {
    std::uint64_t off = kHeaderBytes;
    std::vector<std::uint64_t> offsets;
    for (const Part& p : parts) {
        off = (off + kAlign - 1) / kAlign * kAlign;
        offsets.push_back(off);
        off += std::uint64_t(p.elem) * p.count;
    }
    std::vector<unsigned char> out(off);  // zeroed: the padding is part of the checksum
    unsigned char* h = out.data();
    std::copy(head, head + kHeaderBytes, h);
    std::copy(std::begin(kMagic), std::end(kMagic), h + kOffMagic);
    put<std::uint32_t>(h, kOffVersion, kSavedFormatVersion);
    put<std::uint32_t>(h, kOffHeaderSize, std::uint32_t(kHeaderBytes));
    put<std::uint32_t>(h, kOffWidth, std::uint32_t(width));
    put<std::uint32_t>(h, kOffFlags, quantized ? 1u : 0u);
    put<std::uint32_t>(h, kOffSectionCount, std::uint32_t(parts.size()));
    put<std::uint64_t>(h, kOffFileSize, off);
    put<std::uint64_t>(h, kOffTriangles, mesh.triangles.size());
    put<std::uint64_t>(h, kOffVertices, mesh.positions.size());
    put<std::uint64_t>(h, kOffMeshHash, mesh_hash(mesh));
    for (std::size_t i = 0; i < parts.size(); ++i) {
        const Part& p = parts[i];
        const std::size_t e = kOffSections + i * kSectionBytes;
        put<std::uint32_t>(h, e, std::uint32_t(p.id));
        put<std::uint32_t>(h, e + 4, p.elem);
        put<std::uint64_t>(h, e + 8, offsets[i]);
        put<std::uint64_t>(h, e + 16, p.count);
        if (p.count) std::memcpy(h + offsets[i], p.data, std::size_t(p.elem * p.count));
    }
    put<std::uint64_t>(h, kOffPayloadHash, xxh64(std::span(out).subspan(kHeaderBytes)));
    put<std::uint64_t>(h, kOffHeaderHash, xxh64(std::span(out).first(kOffHeaderHash)));
    return out;
}

void check_mesh(const Mesh& mesh, std::size_t tree_triangles, const char* what) {
    if (mesh.triangles.size() != tree_triangles)
        throw Error(std::string("save: the mesh has ") + std::to_string(mesh.triangles.size()) + " triangles, the " +
                    what + " was built from " + std::to_string(tree_triangles));
}

}  // namespace
}  // namespace store::detail

using namespace store::detail;

std::vector<unsigned char> save_bytes(const Bvh2& bvh, const Mesh& mesh) {
    check_mesh(mesh, bvh.stats().triangles, "bvh2");
    unsigned char head[kHeaderBytes] = {};
    put_build(head, bvh.options());
    put_bounds(head, bvh.bounds());
    const BuildStats& s = bvh.stats();
    put<double>(head, kOffStats + 0, s.build_ms);
    put<std::uint64_t>(head, kOffStats + 8, s.nodes);
    put<std::uint64_t>(head, kOffStats + 16, s.leaves);
    put<std::uint64_t>(head, kOffStats + 24, s.triangles);
    put<std::int64_t>(head, kOffStats + 32, s.depth);
    put<double>(head, kOffStats + 40, s.sah_cost);
    put<double>(head, kOffStats + 48, s.bytes_per_triangle);
    const Part parts[] = {part(Section::bvh2_nodes, bvh.nodes()), part(Section::prim_ids, bvh.prim_ids()),
                          part(Section::gathered, bvh.triangles()), part(Section::positions, mesh.positions),
                          part(Section::triangles, mesh.triangles)};
    return assemble(head, 2, false, mesh, parts);
}

template <int N>
std::vector<unsigned char> save_bytes(const BvhN<N>& bvh, const Mesh& mesh) {
    check_mesh(mesh, bvh.stats().triangles, "wide tree");
    unsigned char head[kHeaderBytes] = {};
    // A wide tree's BVH2 options are not kept by the tree: the file records
    // the defaults with the intersection cost the build used.
    BuildOptions b2;
    b2.intersection_cost = bvh.options().bvh2_intersection_cost;
    put_build(head, b2);
    const WideOptions& o = bvh.options();
    put<std::uint32_t>(head, kOffWide + 0, std::uint32_t(o.collapse));
    put<std::int32_t>(head, kOffWide + 4, o.max_leaf_size);
    put<float>(head, kOffWide + 8, o.node_cost);
    put<float>(head, kOffWide + 12, o.block_cost);
    put<std::int32_t>(head, kOffWide + 16, o.threads);
    put<float>(head, kOffWide + 20, o.bvh2_intersection_cost);
    put<std::uint32_t>(head, kOffWide + 24, o.quantized_nodes ? 1u : 0u);
    put_bounds(head, bvh.bounds());
    const WideStats& s = bvh.stats();
    put<double>(head, kOffStats + 0, s.build_ms);
    put<std::uint64_t>(head, kOffStats + 8, s.nodes);
    put<std::uint64_t>(head, kOffStats + 16, s.leaves);
    put<std::uint64_t>(head, kOffStats + 24, s.blocks);
    put<std::uint64_t>(head, kOffStats + 32, s.triangles);
    put<std::uint64_t>(head, kOffStats + 40, s.shared_blocks);
    put<std::int64_t>(head, kOffStats + 48, s.width);
    put<std::int64_t>(head, kOffStats + 56, s.depth);
    put<double>(head, kOffStats + 64, s.sah_cost);
    put<double>(head, kOffStats + 72, s.bytes_per_triangle);
    put<double>(head, kOffStats + 80, s.fill_rate);
    put<double>(head, kOffStats + 88, s.block_fill);
    const Part parts[] = {part(Section::wide_nodes, bvh.nodes()), part(Section::qnodes, bvh.qnodes()),
                          part(Section::blocks, bvh.blocks()), part(Section::positions, mesh.positions),
                          part(Section::triangles, mesh.triangles)};
    return assemble(head, N, o.quantized_nodes, mesh, parts);
}

void save(const Bvh2& bvh, const Mesh& mesh, const std::filesystem::path& file) {
    io::write_file_atomic(file, save_bytes(bvh, mesh));
}

template <int N>
void save(const BvhN<N>& bvh, const Mesh& mesh, const std::filesystem::path& file) {
    io::write_file_atomic(file, save_bytes(bvh, mesh));
}

#define SIMDBVH_STORE_SAVE(N)                                                       \
    template std::vector<unsigned char> save_bytes<N>(const BvhN<N>&, const Mesh&); \
    template void save<N>(const BvhN<N>&, const Mesh&, const std::filesystem::path&);
SIMDBVH_STORE_SAVE(4)
SIMDBVH_STORE_SAVE(8)
SIMDBVH_STORE_SAVE(16)
#undef SIMDBVH_STORE_SAVE

}  // namespace simdbvh
