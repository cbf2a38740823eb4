#pragma once
// PLY header model shared by the size limit (size_limit_formats.cpp) and the
// body parser (load_ply.cpp).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "simdbvh/io/internal/text.h"

namespace simdbvh::io::detail::ply {

enum class Type : std::uint8_t { i8, u8, i16, u16, i32, u32, f32, f64 };
std::size_t type_size(Type t);
inline bool is_int(Type t) { return t != Type::f32 && t != Type::f64; }

struct Property {
    std::string name;
    bool list = false;
    Type type = Type::f32;       // scalar type, or the list's item type
    Type count_type = Type::u8;  // list only
};
struct Element {
    std::string name;
    std::uint64_t count = 0;
    std::size_t header_line = 0;
    std::vector<Property> props;
};
enum class Format { ascii, binary_le, binary_be };

struct Header {
    Format format = Format::ascii;
    std::vector<Element> elements;
    std::size_t body = 0;   // offset of the first byte after end_header
    std::size_t lines = 0;  // header lines (for line numbers in the body)
};

// Parses the header in data[0, size) (a UTF-8 BOM is skipped). Throws for a
// bad first line or a malformed header line; nullopt when there is no
// end_header in the data.
std::optional<Header> parse_header(const std::string& file, const char* data, std::size_t size);

// The vertex_indices (or vertex_index) list of the "face" element, -1 if none.
int face_list(const std::string& file, const Element& face);

// Which properties the mesh needs.
struct Layout {
    const Element* vert = nullptr;
    const Element* face = nullptr;
    int ix = -1, iy = -1, iz = -1, iface = -1;
    std::uint64_t nv = 0;
    int coord(std::size_t i) const { return int(i) == ix ? 0 : int(i) == iy ? 1 : int(i) == iz ? 2 : -1; }
};

// Collects vertices and fan-triangulated faces; checks indices.
struct Builder {
    const std::string& file;
    std::uint64_t nv;
    Mesh mesh;
    std::uint64_t tri_id = 0;
    std::vector<std::uint32_t> poly;

    void add_face(std::uint64_t face_id, std::size_t line) {
        if (poly.size() < 3)
            fail(file, line,
                 "face " + std::to_string(face_id) + " has " + std::to_string(poly.size()) +
                     " vertices; at least 3 needed");
        for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
            if (tri_id >= kMaxTriangles - 1)
                fail(file, line, "more than " + std::to_string(kMaxTriangles - 1) + " triangles");
            mesh.triangles.push_back(Triangle{poly[0], poly[k], poly[k + 1]});
            ++tri_id;
        }
    }
    void add_index(std::int64_t idx, std::uint64_t face_id, std::size_t k, std::size_t line) {
        if (idx < 0 || std::uint64_t(idx) >= nv) {
            const std::uint64_t tri = tri_id + (k < 3 ? 0 : k - 2);
            fail(file, line,
                 "triangle " + std::to_string(tri) + " (face " + std::to_string(face_id) + ") has vertex index " +
                     std::to_string(idx) + " out of range (" + std::to_string(nv) + " vertices)");
        }
        poly.push_back(std::uint32_t(idx));
    }
};

// Reads the elements in [b, e) (the bytes after the header, `line0` header lines).
Mesh parse_body(const std::string& file, const Header& h, const Layout& l, const char* b, const char* e,
                std::size_t line0);

}  // namespace simdbvh::io::detail::ply
