#pragma once
// Saved structures (docs/saved_format.md): a BVH2 or a BVH4/8/16 (full or
// quantized nodes) and the mesh it was built from, in one little-endian file
// whose arrays start on 64-byte boundaries, checked by XXH64 checksums over
// the header and over every byte after it. Build once, load in milliseconds:
// a load copies each array from the file (read, or mapped read-only) into the
// structure, after the checksums and a structural check (every child, block
// and triangle id in range, the depth within the traversal stack), so a
// loaded tree traces bit-identically to the saved one and a damaged or
// crafted file is a simdbvh::Error naming the file and the problem.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/bvh8/bvh8.h"
#include "simdbvh/kernels/error.h"  // simdbvh::Error, thrown by everything declared here
#include "simdbvh/kernels/mesh.h"

namespace simdbvh {

inline constexpr std::uint32_t kSavedFormatVersion = 1;

// What a saved file holds, from its header alone (inspect).
struct SavedInfo {
    std::uint32_t version = 0;
    int width = 0;  // 2: a Bvh2; 4, 8, 16: a BvhN
    bool quantized = false;
    std::uint64_t file_bytes = 0, triangles = 0, vertices = 0;
    std::uint64_t mesh_hash = 0;     // mesh_hash() of the mesh the tree was built from
    std::uint64_t payload_hash = 0;  // XXH64 of every byte after the header
    BuildOptions build;              // the BVH2 options (a wide tree: the topology's)
    WideOptions wide;                // width > 2 only
    BuildStats bvh2_stats;           // width 2 only
    WideStats wide_stats;            // width > 2 only
    Aabb bounds;
    std::uint64_t node_bytes = 0, block_bytes = 0, qnode_bytes = 0, mesh_bytes = 0;
};
std::string kind_name(const SavedInfo& info);  // "bvh2", "bvh8", "bvh8 (quantized nodes)"

struct LoadOptions {
    // true: the file is mapped read-only (mmap) and its arrays are copied from
    // the mapping; false: it is read (read(2)) into memory first. Same result.
    bool map = true;
    // false skips the payload checksum (the header's checksum, the section
    // bounds and the structural check still run): a flipped byte in a vertex
    // or a box then goes unnoticed. For files this process wrote itself.
    bool verify = true;
    // When set: the file must have been built from this mesh (same triangle
    // count and mesh_hash), else an Error.
    const Mesh* mesh = nullptr;
};

template <class T>
struct Saved {
    T bvh;
    Mesh mesh;
};

// The XXH64 (seed 0) of the positions' bytes, then of the triangles' bytes
// with the first as seed: what a saved file records of its mesh.
std::uint64_t mesh_hash(const Mesh& mesh);
// XXH64 (Collet's xxHash, 64-bit) of `bytes` with `seed`.
std::uint64_t xxh64(std::span<const unsigned char> bytes, std::uint64_t seed = 0);

// The file's bytes. `mesh` must be the one the tree was built from (its
// triangle count is checked; the tree holds its own copies of the triangles
// and the file keeps the mesh so a load needs nothing else).
std::vector<unsigned char> save_bytes(const Bvh2& bvh, const Mesh& mesh);
template <int N>
std::vector<unsigned char> save_bytes(const BvhN<N>& bvh, const Mesh& mesh);
// Written through io::write_file_atomic: a temporary file renamed over
// `file`, never a partial file.
void save(const Bvh2& bvh, const Mesh& mesh, const std::filesystem::path& file);
template <int N>
void save(const BvhN<N>& bvh, const Mesh& mesh, const std::filesystem::path& file);

// T = Bvh2, Bvh4, Bvh8 or Bvh16; a file holding another width is an Error.
template <class T>
T load(const std::filesystem::path& file, const LoadOptions& opts = {});
template <class T>
Saved<T> load_with_mesh(const std::filesystem::path& file, const LoadOptions& opts = {});
// From bytes (pickling); `name` is what errors call them.
template <class T>
Saved<T> load_bytes(std::span<const unsigned char> bytes, std::string_view name, const LoadOptions& opts = {});

// The header (its checksum and the section table checked, not the payload).
SavedInfo inspect(const std::filesystem::path& file);
SavedInfo inspect_bytes(std::span<const unsigned char> bytes, std::string_view name);
// True when the file starts with the format's magic bytes.
bool is_saved_file(const std::filesystem::path& file);

}  // namespace simdbvh
