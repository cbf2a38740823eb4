// load / load_with_mesh / load_bytes / inspect: the header and its checksum,
// the section table against the file's size, the payload checksum, then the
// arrays copied into the structure and checked so no index can leave them
// (docs/saved_format.md, "What a load checks").
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <limits>
#include <type_traits>

#include "format.h"
#include "simdbvh/io/internal/text.h"
#include "simdbvh/store/store.h"

namespace simdbvh {

using namespace store::detail;

namespace {

[[noreturn]] void fail(std::string_view name, const std::string& problem) {
    throw Error(io::detail::printable(name) + ": " + problem);
}

std::string hex(std::uint64_t v) {
    char buf[19];
    std::snprintf(buf, sizeof buf, "0x%016llx", static_cast<unsigned long long>(v));
    return buf;
}

constexpr int kSectionIds = 9;

struct Parsed {
    SavedInfo info;
    std::span<const unsigned char> sec[kSectionIds];  // by Section id; empty when absent
    std::uint64_t count[kSectionIds] = {};
    bool present[kSectionIds] = {};
};

// The element size of a wide tree's node kind; the width was checked (2, 4, 8 or 16) with the header.
template <template <int> class Node>
std::uint32_t node_bytes(int width) {
    if (width == 2) return 0;  // no wide sections in a binary tree's file
    return with_width(width, [](auto n) { return std::uint32_t(sizeof(Node<decltype(n)::value>)); });
}

std::uint32_t expected_elem(Section s, int width) {
    switch (s) {
    case Section::positions: return sizeof(Vec3);
    case Section::triangles: return sizeof(Triangle);
    case Section::wide_nodes: return node_bytes<NodeN>(width);
    case Section::blocks: return sizeof(Tri8);
    case Section::qnodes: return node_bytes<QNodeN>(width);
    case Section::bvh2_nodes: return sizeof(Node2);
    case Section::prim_ids: return sizeof(std::uint32_t);
    case Section::gathered: return sizeof(TriangleVerts);
    }
    return 0;
}

// The header and the section table; the payload checksum when `verify`.
Parsed parse(std::span<const unsigned char> bytes, std::string_view name, bool verify) {
    const unsigned char* h = bytes.data();
    if (bytes.size() < sizeof kMagic || !std::equal(std::begin(kMagic), std::end(kMagic), h))
        fail(name, "not a simdbvh saved structure (wrong magic bytes)");
    if (bytes.size() < kHeaderBytes)
        fail(name, "truncated: " + std::to_string(bytes.size()) + " bytes, less than the " +
                       std::to_string(kHeaderBytes) + "-byte header");
    Parsed p;
    SavedInfo& in = p.info;
    in.version = get<std::uint32_t>(h, kOffVersion);
    if (in.version != kSavedFormatVersion)
        fail(name, "format version " + std::to_string(in.version) + ", this build reads version " +
                       std::to_string(kSavedFormatVersion) + " (save it again with this build)");
    if (get<std::uint32_t>(h, kOffHeaderSize) != kHeaderBytes) fail(name, "header size is not 512 bytes");
    const std::uint64_t header_hash = xxh64(bytes.first(kOffHeaderHash));
    if (header_hash != get<std::uint64_t>(h, kOffHeaderHash))
        fail(name, "header checksum mismatch (XXH64 " + hex(header_hash) + ", recorded " +
                       hex(get<std::uint64_t>(h, kOffHeaderHash)) + "): the file is damaged");
    in.file_bytes = get<std::uint64_t>(h, kOffFileSize);
    if (bytes.size() < in.file_bytes)
        fail(name, "truncated: " + std::to_string(bytes.size()) + " bytes of " + std::to_string(in.file_bytes));
    if (bytes.size() > in.file_bytes)
        fail(name, std::to_string(bytes.size() - in.file_bytes) + " bytes after the end the header records (" +
                       std::to_string(in.file_bytes) + ")");
    in.width = int(get<std::uint32_t>(h, kOffWidth));
    if (in.width != 2 && in.width != 4 && in.width != 8 && in.width != 16)
        fail(name, "unknown tree width " + std::to_string(in.width));
    const std::uint32_t flags = get<std::uint32_t>(h, kOffFlags);
    if (flags > 1u || (flags && (in.width == 2 || in.width == 4)))
        fail(name, "unknown flags " + std::to_string(flags) + " for width " + std::to_string(in.width));
    in.quantized = flags & 1u;
    in.triangles = get<std::uint64_t>(h, kOffTriangles);
    in.vertices = get<std::uint64_t>(h, kOffVertices);
    if (in.triangles > kMaxTriangles) fail(name, "more triangles than a tree holds");
    in.mesh_hash = get<std::uint64_t>(h, kOffMeshHash);
    in.payload_hash = get<std::uint64_t>(h, kOffPayloadHash);

    BuildOptions& b = in.build;
    const std::uint32_t builder = get<std::uint32_t>(h, kOffBuild);
    if (builder > std::uint32_t(Builder::variance)) fail(name, "unknown builder " + std::to_string(builder));
    b.builder = Builder(builder);
    b.bins = get<std::int32_t>(h, kOffBuild + 4);
    b.max_leaf_size = get<std::int32_t>(h, kOffBuild + 8);
    b.min_leaf_size = get<std::int32_t>(h, kOffBuild + 12);
    b.traversal_cost = get<float>(h, kOffBuild + 16);
    b.intersection_cost = get<float>(h, kOffBuild + 20);
    b.max_depth = get<std::int32_t>(h, kOffBuild + 24);
    b.threads = get<std::int32_t>(h, kOffBuild + 28);
    const float lo[3] = {get<float>(h, kOffBounds), get<float>(h, kOffBounds + 4), get<float>(h, kOffBounds + 8)};
    const float hi[3] = {get<float>(h, kOffBounds + 12), get<float>(h, kOffBounds + 16),
                         get<float>(h, kOffBounds + 20)};
    in.bounds.lo = {lo[0], lo[1], lo[2]};
    in.bounds.hi = {hi[0], hi[1], hi[2]};
    auto stat_u = [&](int i) { return std::size_t(get<std::uint64_t>(h, kOffStats + 8 * i)); };
    auto stat_i = [&](int i) { return int(get<std::int64_t>(h, kOffStats + 8 * i)); };
    auto stat_d = [&](int i) { return get<double>(h, kOffStats + 8 * i); };
    if (in.width == 2) {
        BuildStats& s = in.bvh2_stats;
        s = {stat_d(0), stat_u(1), stat_u(2), stat_u(3), stat_i(4), stat_d(5), stat_d(6)};
    } else {
        WideOptions& o = in.wide;
        const std::uint32_t collapse = get<std::uint32_t>(h, kOffWide);
        if (collapse > std::uint32_t(Collapse::greedy)) fail(name, "unknown collapse " + std::to_string(collapse));
        o.collapse = Collapse(collapse);
        o.max_leaf_size = get<std::int32_t>(h, kOffWide + 4);
        o.node_cost = get<float>(h, kOffWide + 8);
        o.block_cost = get<float>(h, kOffWide + 12);
        o.threads = get<std::int32_t>(h, kOffWide + 16);
        o.bvh2_intersection_cost = get<float>(h, kOffWide + 20);
        o.quantized_nodes = get<std::uint32_t>(h, kOffWide + 24) != 0;
        if (o.quantized_nodes != in.quantized) fail(name, "the options and the flags disagree on quantized nodes");
        WideStats& s = in.wide_stats;
        s.build_ms = stat_d(0);
        s.nodes = stat_u(1);
        s.leaves = stat_u(2);
        s.blocks = stat_u(3);
        s.triangles = stat_u(4);
        s.shared_blocks = stat_u(5);
        s.width = stat_i(6);
        s.depth = stat_i(7);
        s.sah_cost = stat_d(8);
        s.bytes_per_triangle = stat_d(9);
        s.fill_rate = stat_d(10);
        s.block_fill = stat_d(11);
    }

    const std::uint32_t sections = get<std::uint32_t>(h, kOffSectionCount);
    if (sections > std::uint32_t(kMaxSections)) fail(name, std::to_string(sections) + " sections, at most 6");
    for (std::uint32_t i = 0; i < sections; ++i) {
        const std::size_t e = kOffSections + i * kSectionBytes;
        const std::uint32_t id = get<std::uint32_t>(h, e);
        const std::uint32_t elem = get<std::uint32_t>(h, e + 4);
        const std::uint64_t off = get<std::uint64_t>(h, e + 8), count = get<std::uint64_t>(h, e + 16);
        if (id == 0 || id >= std::uint32_t(kSectionIds)) fail(name, "unknown section id " + std::to_string(id));
        const Section s = Section(id);
        const std::string sname = std::string("section '") + section_name(s) + "'";
        const bool wide = s == Section::wide_nodes || s == Section::blocks || s == Section::qnodes;
        const bool binary = s == Section::bvh2_nodes || s == Section::prim_ids || s == Section::gathered;
        if ((in.width == 2 && wide) || (in.width != 2 && binary))
            fail(name, sname + " does not belong to a tree of width " + std::to_string(in.width));
        if (p.present[id]) fail(name, sname + " appears twice");
        if (elem != expected_elem(s, in.width))
            fail(name, sname + ": elements of " + std::to_string(elem) + " bytes, this build's are " +
                           std::to_string(expected_elem(s, in.width)));
        if (off % kAlign || off < kHeaderBytes)
            fail(name, sname + " at offset " + std::to_string(off) + ": not 64-byte aligned after the header");
        if (off > in.file_bytes || count > (in.file_bytes - off) / elem)
            fail(name, sname + " (offset " + std::to_string(off) + ", " + std::to_string(count) + " x " +
                           std::to_string(elem) + " bytes) lies outside the file (" + std::to_string(in.file_bytes) +
                           " bytes)");
        p.present[id] = true;
        p.count[id] = count;
        p.sec[id] = bytes.subspan(std::size_t(off), std::size_t(count * elem));
    }
    const Section need2[] = {Section::positions, Section::triangles, Section::bvh2_nodes, Section::prim_ids,
                             Section::gathered};
    const Section needn[] = {Section::positions, Section::triangles, Section::wide_nodes, Section::qnodes,
                             Section::blocks};
    for (Section s : in.width == 2 ? std::span<const Section>(need2) : std::span<const Section>(needn))
        if (!p.present[int(s)]) fail(name, std::string("section '") + section_name(s) + "' is missing");
    if (p.count[int(Section::triangles)] != in.triangles || p.count[int(Section::positions)] != in.vertices)
        fail(name, "the mesh sections disagree with the header's triangle and vertex counts");
    in.mesh_bytes = p.sec[int(Section::positions)].size() + p.sec[int(Section::triangles)].size();
    if (in.width == 2) {
        in.node_bytes = p.sec[int(Section::bvh2_nodes)].size();
        in.block_bytes = p.sec[int(Section::prim_ids)].size() + p.sec[int(Section::gathered)].size();
    } else {
        in.node_bytes = p.sec[int(Section::wide_nodes)].size();
        in.qnode_bytes = p.sec[int(Section::qnodes)].size();
        in.block_bytes = p.sec[int(Section::blocks)].size();
    }
    if (verify) {
        const std::uint64_t got = xxh64(bytes.subspan(kHeaderBytes));
        if (got != in.payload_hash)
            fail(name, "checksum mismatch (XXH64 of bytes 512.." + std::to_string(bytes.size()) + " is " + hex(got) +
                           ", recorded " + hex(in.payload_hash) + "): the file is damaged");
    }
    return p;
}

template <class V>
void copy_into(V& v, std::span<const unsigned char> s, std::uint64_t count) {
    v.resize(std::size_t(count));
    if (count) std::memcpy(static_cast<void*>(v.data()), s.data(), s.size());
}

template <class T>
constexpr int width_of() {
    if constexpr (std::is_same_v<T, Bvh2>) return 2;
    else return T::kWidth;
}

std::string tree_name(int width, bool quantized = false) {
    return "bvh" + std::to_string(width) + (quantized ? " (quantized nodes)" : "");
}

// A read-only mapping or a 64-byte aligned copy of a regular file.
class FileBytes {
public:
    FileBytes(const std::filesystem::path& file, bool map) {
        const std::string name = file.string();
        fd_ = ::open(name.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
        if (fd_ < 0) fail(name, std::string("cannot open: ") + std::strerror(errno));
        struct stat st {};
        if (::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode)) {
            const bool dir = S_ISDIR(st.st_mode);
            ::close(fd_);
            fail(name, dir ? "is a directory" : "not a regular file");
        }
        size_ = std::size_t(st.st_size);
        if (size_ == 0) {
            ::close(fd_);
            fail(name, "empty file (not a simdbvh saved structure)");
        }
        if (map) {
            // MAP_POPULATE: the page tables filled in one call, not one fault per 4 KiB page as the
            // checksum and the copies first touch them.
            void* p = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE | MAP_POPULATE, fd_, 0);
            if (p == MAP_FAILED) {
                ::close(fd_);
                fail(name, std::string("cannot map: ") + std::strerror(errno));
            }
            ::madvise(p, size_, MADV_SEQUENTIAL);
            map_ = static_cast<unsigned char*>(p);
        } else {
            buf_.resize(size_);
            std::size_t done = 0;
            while (done < size_) {
                const ssize_t r = ::read(fd_, buf_.data() + done, size_ - done);
                if (r < 0 && errno == EINTR) continue;
                if (r <= 0) {
                    ::close(fd_);
                    fail(name, r == 0 ? "truncated while reading" : std::string("read: ") + std::strerror(errno));
                }
                done += std::size_t(r);
            }
        }
    }
    ~FileBytes() {
        if (map_) ::munmap(map_, size_);
        ::close(fd_);
    }
    FileBytes(const FileBytes&) = delete;
    FileBytes& operator=(const FileBytes&) = delete;
    std::span<const unsigned char> bytes() const { return map_ ? std::span(map_, size_) : std::span(buf_); }

private:
    int fd_ = -1;
    std::size_t size_ = 0;
    unsigned char* map_ = nullptr;
    LargeVector<unsigned char, 64> buf_;
};

}  // namespace

// Fills the trees' private members (a friend of Bvh2 and BvhN) and checks
// every index traversal, refit and the point queries follow.
struct StoreAccess {
    static void check_prims(std::string_view name, std::span<const std::uint32_t> ids, std::uint64_t tris,
                            const char* what) {
        for (std::uint32_t id : ids)
            if (id >= tris && id != kInvalidPrim)
                fail(name,
                     std::string(what) + " holds triangle id " + std::to_string(id) + " of " + std::to_string(tris));
    }

    static Bvh2 bvh2(const Parsed& p, std::string_view name) {
        Bvh2 b;
        copy_into(b.nodes_, p.sec[int(Section::bvh2_nodes)], p.count[int(Section::bvh2_nodes)]);
        copy_into(b.prim_ids_, p.sec[int(Section::prim_ids)], p.count[int(Section::prim_ids)]);
        copy_into(b.tris_, p.sec[int(Section::gathered)], p.count[int(Section::gathered)]);
        b.stats_ = p.info.bvh2_stats;
        b.opts_ = p.info.build;
        const std::size_t n = b.nodes_.size();
        if (b.tris_.size() != b.prim_ids_.size()) fail(name, "gathered triangles and triangle ids differ in count");
        std::vector<std::uint8_t> depth(n, 0);
        for (std::size_t i = 0; i < n; ++i) {
            const Node2& node = b.nodes_[i];
            if (node.count == 0) {
                if (node.first <= i || std::uint64_t(node.first) + 1 >= n)
                    fail(name, "bvh2 node " + std::to_string(i) + " has children outside the tree");
                if (depth[i] >= kMaxDepth) fail(name, "the bvh2 is deeper than the traversal stack allows");
                for (std::uint32_t c : {node.first, node.first + 1})
                    depth[c] = std::max<std::uint8_t>(depth[c], depth[i] + 1);
            } else if (std::uint64_t(node.first) + node.count > b.prim_ids_.size()) {
                fail(name, "bvh2 leaf " + std::to_string(i) + " lies outside the triangle ids");
            }
        }
        check_prims(name, b.prim_ids_, p.info.triangles, "the bvh2");
        for (std::uint32_t id : b.prim_ids_)
            if (id == kInvalidPrim) fail(name, "the bvh2 holds an invalid triangle id");
        if (b.stats_.triangles != p.info.triangles) fail(name, "the bvh2 statistics disagree with the mesh");
        return b;
    }

    template <int N>
    static BvhN<N> wide(const Parsed& p, std::string_view name) {
        BvhN<N> b;
        copy_into(b.nodes_, p.sec[int(Section::wide_nodes)], p.count[int(Section::wide_nodes)]);
        copy_into(b.qnodes_, p.sec[int(Section::qnodes)], p.count[int(Section::qnodes)]);
        copy_into(b.blocks_, p.sec[int(Section::blocks)], p.count[int(Section::blocks)]);
        b.stats_ = p.info.wide_stats;
        b.opts_ = p.info.wide;
        b.bounds_ = p.info.bounds;
        const std::size_t n = b.nodes_.size();
        if (b.stats_.width != N || b.stats_.triangles != p.info.triangles)
            fail(name, "the tree statistics disagree with its width or the mesh");
        if (b.qnodes_.size() != (b.opts_.quantized_nodes ? n : 0))
            fail(name, "quantized nodes: " + std::to_string(b.qnodes_.size()) + ", expected " +
                           std::to_string(b.opts_.quantized_nodes ? n : 0));
        constexpr float inf = std::numeric_limits<float>::infinity();
        std::vector<std::uint8_t> depth(n, 0);
        for (std::size_t i = 0; i < n; ++i) {
            const NodeN<N>& node = b.nodes_[i];
            for (int s = 0; s < N; ++s) {
                const ChildN<N>& c = node.children[s];
                // The message is made only on failure: this loop runs for every slot of every node.
                auto where = [&] { return "node " + std::to_string(i) + " slot " + std::to_string(s); };
                if (c.is_empty()) {
                    const BoxN<N>& x = node.boxes;
                    if (!(x.lo_x[s] == inf && x.lo_y[s] == inf && x.lo_z[s] == inf && x.hi_x[s] == -inf &&
                          x.hi_y[s] == -inf && x.hi_z[s] == -inf))
                        fail(name, where() + ": an empty slot with a box");
                } else if (c.is_inner()) {
                    if (c.index <= i || c.index >= n) fail(name, where() + ": a child outside the tree");
                    if (depth[i] >= kMaxDepth) fail(name, "the tree is deeper than the traversal stack allows");
                    depth[c.index] = std::max<std::uint8_t>(depth[c.index], depth[i] + 1);
                } else if (c.blocks() == 0 || std::uint64_t(c.index) + c.blocks() > b.blocks_.size()) {
                    fail(name, where() + ": a leaf outside the triangle blocks");
                }
            }
            if (b.opts_.quantized_nodes) {
                const QNodeN<N>& q = b.qnodes_[i];
                if (std::memcmp(q.children, node.children, sizeof node.children) != 0)
                    fail(name, "quantized node " + std::to_string(i) + " disagrees with node " + std::to_string(i));
                for (int a = 0; a < 3; ++a)
                    if (q.boxes.exp[a] < 1 || q.boxes.exp[a] > 254)
                        fail(name, "quantized node " + std::to_string(i) + ": step exponent out of range");
                for (int s = 0; s < N; ++s)
                    if (bool((q.boxes.valid >> s) & 1u) == node.children[s].is_empty())
                        fail(name, "quantized node " + std::to_string(i) + ": slot mask disagrees with the slots");
            }
        }
        for (const Tri8& t : b.blocks_) check_prims(name, t.prim, p.info.triangles, "a triangle block");
        return b;
    }
};

namespace {

template <class T>
T make_tree(const Parsed& p, std::string_view name) {
    if constexpr (std::is_same_v<T, Bvh2>) return StoreAccess::bvh2(p, name);
    else return StoreAccess::wide<T::kWidth>(p, name);
}

template <class T>
Saved<T> from_bytes(std::span<const unsigned char> bytes, std::string_view name, const LoadOptions& opts,
                    bool with_mesh) {
    const Parsed p = parse(bytes, name, opts.verify);
    constexpr int w = width_of<T>();
    if (p.info.width != w)
        fail(name, "holds a " + tree_name(p.info.width, p.info.quantized) + ", not the " + tree_name(w) + " asked for");
    if (opts.mesh) {
        const Mesh& m = *opts.mesh;
        if (m.triangles.size() != p.info.triangles || mesh_hash(m) != p.info.mesh_hash)
            fail(name, "was built from another mesh (" + std::to_string(p.info.triangles) + " triangles, mesh hash " +
                           hex(p.info.mesh_hash) + "), not the one given (" + std::to_string(m.triangles.size()) +
                           " triangles, mesh hash " + hex(mesh_hash(m)) + ")");
    }
    Saved<T> out{make_tree<T>(p, name), {}};
    if (with_mesh) {
        copy_into(out.mesh.positions, p.sec[int(Section::positions)], p.info.vertices);
        copy_into(out.mesh.triangles, p.sec[int(Section::triangles)], p.info.triangles);
        try {
            validate(out.mesh);
        } catch (const Error& e) {
            fail(name, std::string("its mesh: ") + e.what());
        }
    }
    return out;
}

}  // namespace

std::string kind_name(const SavedInfo& info) { return tree_name(info.width, info.quantized); }

template <class T>
Saved<T> load_bytes(std::span<const unsigned char> bytes, std::string_view name, const LoadOptions& opts) {
    return from_bytes<T>(bytes, name, opts, true);
}

template <class T>
T load(const std::filesystem::path& file, const LoadOptions& opts) {
    const FileBytes f(file, opts.map);
    return std::move(from_bytes<T>(f.bytes(), file.string(), opts, false).bvh);
}

template <class T>
Saved<T> load_with_mesh(const std::filesystem::path& file, const LoadOptions& opts) {
    const FileBytes f(file, opts.map);
    return from_bytes<T>(f.bytes(), file.string(), opts, true);
}

SavedInfo inspect_bytes(std::span<const unsigned char> bytes, std::string_view name) {
    return parse(bytes, name, false).info;
}

SavedInfo inspect(const std::filesystem::path& file) {
    const FileBytes f(file, true);
    return parse(f.bytes(), file.string(), false).info;
}

bool is_saved_file(const std::filesystem::path& file) {
    const int fd = ::open(file.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) return false;
    unsigned char m[sizeof kMagic] = {};
    struct stat st {};
    const bool ok = ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && ::read(fd, m, sizeof m) == ssize_t(sizeof m) &&
                    std::equal(std::begin(kMagic), std::end(kMagic), m);
    ::close(fd);
    return ok;
}

#define SIMDBVH_STORE_LOAD(T)                                                              \
    template T load<T>(const std::filesystem::path&, const LoadOptions&);                  \
    template Saved<T> load_with_mesh<T>(const std::filesystem::path&, const LoadOptions&); \
    template Saved<T> load_bytes<T>(std::span<const unsigned char>, std::string_view, const LoadOptions&);
SIMDBVH_STORE_LOAD(Bvh2)
SIMDBVH_STORE_LOAD(Bvh4)
SIMDBVH_STORE_LOAD(Bvh8)
SIMDBVH_STORE_LOAD(Bvh16)
#undef SIMDBVH_STORE_LOAD

}  // namespace simdbvh
