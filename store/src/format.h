#pragma once
// The saved file's layout (docs/saved_format.md): byte offsets of the header
// fields and the section ids. Little-endian; the arrays are the in-memory
// structures' bytes (their sizes fixed by static_asserts here and beside the
// types), so a change to any of them is a new kSavedFormatVersion.
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/bvh8/bvh8.h"

namespace simdbvh::store::detail {

static_assert(std::endian::native == std::endian::little, "the saved format is little-endian, as is every x86 CPU");
static_assert(sizeof(Vec3) == 12 && sizeof(Triangle) == 12 && sizeof(Node2) == 32 && sizeof(TriangleVerts) == 36);
static_assert(sizeof(Tri8) == 320 && sizeof(Node4) == 128 && sizeof(Node8) == 256 && sizeof(Node16) == 512);
static_assert(sizeof(QNode8) == 128 && sizeof(QNode16) == 256);

inline constexpr unsigned char kMagic[8] = {0x89, 'S', 'B', 'V', 'H', '\r', '\n', 0x1a};
inline constexpr std::size_t kHeaderBytes = 512;
inline constexpr std::size_t kAlign = 64;  // every section starts on a cache line
inline constexpr int kMaxSections = 6;

// Header field offsets.
enum Off : std::size_t {
    kOffMagic = 0,
    kOffVersion = 8,
    kOffHeaderSize = 12,
    kOffWidth = 16,
    kOffFlags = 20,  // bit 0: quantized nodes
    kOffSectionCount = 24,
    kOffFileSize = 32,
    kOffTriangles = 40,
    kOffVertices = 48,
    kOffMeshHash = 56,
    kOffPayloadHash = 64,
    kOffBuild =
        72,  // BuildOptions: builder, bins, max_leaf, min_leaf, traversal_cost, intersection_cost, max_depth, threads
    kOffWide =
        104,  // WideOptions: collapse, max_leaf, node_cost, block_cost, threads, bvh2_intersection_cost, quantized
    kOffBounds = 132,      // lo x y z, hi x y z
    kOffStats = 160,       // 12 eight-byte fields (BuildStats or WideStats, in declaration order)
    kOffSections = 256,    // kMaxSections entries of kSectionBytes
    kOffHeaderHash = 504,  // XXH64 of bytes [0, 504)
};
inline constexpr std::size_t kSectionBytes = 32;  // id u32, element size u32, offset u64, count u64, zero u64
static_assert(kOffSections + kMaxSections * kSectionBytes <= kOffHeaderHash);

enum class Section : std::uint32_t {
    positions = 1,   // Vec3
    triangles = 2,   // Triangle (3 x u32)
    wide_nodes = 3,  // NodeN<N>
    blocks = 4,      // Tri8
    qnodes = 5,      // QNodeN<N>
    bvh2_nodes = 6,  // Node2
    prim_ids = 7,    // u32
    gathered = 8,    // TriangleVerts
};
const char* section_name(Section s);

template <class T>
void put(unsigned char* p, std::size_t off, T v) {
    std::memcpy(p + off, &v, sizeof(T));
}
template <class T>
T get(const unsigned char* p, std::size_t off) {
    T v;
    std::memcpy(&v, p + off, sizeof(T));
    return v;
}

}  // namespace simdbvh::store::detail
