// PLY: ASCII, binary_little_endian, binary_big_endian. x, y, z picked by name
// from the "vertex" element (any scalar type); faces from the "face" element's
// list "vertex_indices" (or "vertex_index"); everything else is skipped.
#include <bit>
#include <cstring>
#include <limits>

#include "text.h"

namespace simdbvh::scene::detail {
namespace {

enum class Type : std::uint8_t { i8, u8, i16, u16, i32, u32, f32, f64 };

bool parse_type(std::string_view s, Type& t) {
    struct Name { const char* n; Type t; };
    static const Name names[] = {
        {"char", Type::i8},    {"int8", Type::i8},     {"uchar", Type::u8},   {"uint8", Type::u8},
        {"short", Type::i16},  {"int16", Type::i16},   {"ushort", Type::u16}, {"uint16", Type::u16},
        {"int", Type::i32},    {"int32", Type::i32},   {"uint", Type::u32},   {"uint32", Type::u32},
        {"float", Type::f32},  {"float32", Type::f32}, {"double", Type::f64}, {"float64", Type::f64},
    };
    for (const Name& n : names)
        if (s == n.n) { t = n.t; return true; }
    return false;
}
std::size_t type_size(Type t) {
    switch (t) {
    case Type::i8: case Type::u8: return 1;
    case Type::i16: case Type::u16: return 2;
    case Type::i32: case Type::u32: case Type::f32: return 4;
    case Type::f64: return 8;
    }
    return 1;
}
bool is_int(Type t) { return t != Type::f32 && t != Type::f64; }

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

// A scalar read from binary data: as a float (x, y, z) or an integer (list counts, indices).
struct Binary {
    const unsigned char* p;
    const unsigned char* end;
    bool swap;

    template <class T>
    T raw() {
        unsigned char b[sizeof(T)];
        std::memcpy(b, p, sizeof(T));
        p += sizeof(T);
        if (swap)
            for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
        T v;
        std::memcpy(&v, b, sizeof(T));
        return v;
    }
    float as_float(Type t) {
        switch (t) {
        case Type::i8: return float(raw<std::int8_t>());
        case Type::u8: return float(raw<std::uint8_t>());
        case Type::i16: return float(raw<std::int16_t>());
        case Type::u16: return float(raw<std::uint16_t>());
        case Type::i32: return float(raw<std::int32_t>());
        case Type::u32: return float(raw<std::uint32_t>());
        case Type::f32: return raw<float>();
        case Type::f64: return float(raw<double>());
        }
        return 0;
    }
    std::int64_t as_int(Type t) {
        switch (t) {
        case Type::i8: return raw<std::int8_t>();
        case Type::u8: return raw<std::uint8_t>();
        case Type::i16: return raw<std::int16_t>();
        case Type::u16: return raw<std::uint16_t>();
        case Type::i32: return raw<std::int32_t>();
        case Type::u32: return raw<std::uint32_t>();
        default: return 0;  // float types are rejected for counts and indices up front
        }
    }
};

std::string_view trim(std::string_view s) {
    while (!s.empty() && (is_space(s.back()))) s.remove_suffix(1);
    while (!s.empty() && (is_space(s.front()))) s.remove_prefix(1);
    return s;
}

bool ascii_int_in_range(std::int64_t v, Type t) {
    switch (t) {
    case Type::i8: return v >= -128 && v <= 127;
    case Type::u8: return v >= 0 && v <= 255;
    case Type::i16: return v >= -32768 && v <= 32767;
    case Type::u16: return v >= 0 && v <= 65535;
    case Type::i32: return v >= std::numeric_limits<std::int32_t>::min() && v <= std::numeric_limits<std::int32_t>::max();
    case Type::u32: return v >= 0 && v <= std::numeric_limits<std::uint32_t>::max();
    default: return true;
    }
}

}  // namespace

Mesh load_ply(const std::string& file, const std::vector<char>& data) {
    Lines lines(data.data(), data.data() + data.size());
    std::string_view line;
    if (!lines.next(line) || trim(line) != "ply") fail(file, 1, "not a PLY file (first line must be 'ply')");

    Format format = Format::ascii;
    bool have_format = false, have_end = false;
    std::vector<Element> elements;
    while (lines.next(line)) {
        Tokens tk(line);
        std::string_view kw;
        if (!tk.next(kw)) continue;
        if (kw == "end_header") {
            if (!tk.empty_rest()) fail(file, lines.line, "junk after end_header");
            have_end = true;
            break;
        }
        if (kw == "comment" || kw == "obj_info") continue;
        if (kw == "format") {
            std::string_view f, ver;
            if (!tk.next(f) || !tk.next(ver) || !tk.empty_rest()) fail(file, lines.line, "malformed format line");
            if (f == "ascii") format = Format::ascii;
            else if (f == "binary_little_endian") format = Format::binary_le;
            else if (f == "binary_big_endian") format = Format::binary_be;
            else fail(file, lines.line, "unknown PLY format " + quote(f));
            if (ver != "1.0") fail(file, lines.line, "unsupported PLY version " + quote(ver));
            have_format = true;
        } else if (kw == "element") {
            std::string_view name, count;
            std::int64_t n = 0;
            if (!tk.next(name) || !tk.next(count) || !tk.empty_rest()) fail(file, lines.line, "malformed element line");
            if (!parse_int(count, n) || n < 0) fail(file, lines.line, "bad element count " + quote(count));
            elements.push_back(Element{std::string(name), std::uint64_t(n), lines.line, {}});
        } else if (kw == "property") {
            if (elements.empty()) fail(file, lines.line, "property before any element");
            Property prop;
            std::string_view a, b, c, name;
            if (!tk.next(a)) fail(file, lines.line, "malformed property line");
            if (a == "list") {
                if (!tk.next(b) || !tk.next(c) || !tk.next(name) || !tk.empty_rest())
                    fail(file, lines.line, "malformed list property line");
                prop.list = true;
                if (!parse_type(b, prop.count_type) || !is_int(prop.count_type))
                    fail(file, lines.line, "bad list count type " + quote(b));
                if (!parse_type(c, prop.type)) fail(file, lines.line, "unknown property type " + quote(c));
            } else {
                if (!tk.next(name) || !tk.empty_rest()) fail(file, lines.line, "malformed property line");
                if (!parse_type(a, prop.type)) fail(file, lines.line, "unknown property type " + quote(a));
            }
            prop.name = std::string(name);
            elements.back().props.push_back(std::move(prop));
        }
        // Any other header line (e.g. Blender 2.4's "Created by Blender3D ...") is tolerated and skipped.
    }
    if (!have_end) fail(file, 0, "truncated header (no end_header)");
    if (!have_format) fail(file, 0, "header has no format line");

    // Vertices and faces.
    const Element* vert = nullptr;
    const Element* face = nullptr;
    int ix = -1, iy = -1, iz = -1, iface = -1;
    for (const Element& e : elements) {
        if (e.name == "vertex") {
            if (vert) fail(file, e.header_line, "second 'vertex' element");
            vert = &e;
            for (std::size_t i = 0; i < e.props.size(); ++i) {
                const Property& p = e.props[i];
                int* slot = p.name == "x" ? &ix : p.name == "y" ? &iy : p.name == "z" ? &iz : nullptr;
                if (!slot) continue;
                if (p.list) fail(file, e.header_line, "vertex property " + p.name + " is a list");
                *slot = int(i);
            }
            if (e.count && (ix < 0 || iy < 0 || iz < 0)) fail(file, e.header_line, "vertex element lacks x, y or z");
        } else if (e.name == "face") {
            if (face) fail(file, e.header_line, "second 'face' element");
            face = &e;
            for (std::size_t i = 0; i < e.props.size(); ++i) {
                const Property& p = e.props[i];
                if (p.name == "vertex_indices" || p.name == "vertex_index") {
                    if (!p.list || !is_int(p.type)) fail(file, e.header_line, p.name + " must be a list of integers");
                    if (iface >= 0) fail(file, e.header_line, "two vertex index lists");
                    iface = int(i);
                }
            }
        }
    }
    const std::uint64_t nv = vert ? vert->count : 0;
    if (nv > 0xFFFFFFFFull) fail(file, 0, std::to_string(nv) + " vertices > max " + std::to_string(0xFFFFFFFFull));

    // Counts against the remaining size, before allocating anything.
    const std::size_t body = std::size_t(lines.end - lines.p);
    {
        std::uint64_t need = 0;
        for (const Element& e : elements) {
            std::uint64_t min = 0;
            for (const Property& p : e.props)
                min += format == Format::ascii ? 2 : (p.list ? type_size(p.count_type) : type_size(p.type));
            if (e.count && min == 0)
                fail(file, e.header_line, "element '" + e.name + "' has no properties but count " + std::to_string(e.count));
            if (e.count > (body - std::min<std::uint64_t>(need, body)) / std::max<std::uint64_t>(min, 1))
                fail(file, e.header_line,
                     "element '" + e.name + "' count " + std::to_string(e.count) + " needs at least " +
                         std::to_string(min) + " bytes each but only " + std::to_string(body) +
                         " bytes follow the header");
            need += e.count * min;
        }
    }

    Mesh mesh;
    mesh.positions.reserve(std::size_t(nv));
    if (face) mesh.triangles.reserve(std::size_t(face->count));
    std::uint64_t tri_id = 0;
    std::vector<std::uint32_t> poly;

    auto add_face = [&](std::uint64_t face_id, std::size_t line) {
        if (poly.size() < 3)
            fail(file, line, "face " + std::to_string(face_id) + " has " + std::to_string(poly.size()) + " < 3 vertices");
        for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
            if (tri_id >= kMaxTriangles - 1)
                fail(file, line, "more than " + std::to_string(kMaxTriangles - 1) + " triangles");
            mesh.triangles.push_back(Triangle{poly[0], poly[k], poly[k + 1]});
            ++tri_id;
        }
    };
    auto check_index = [&](std::int64_t idx, std::uint64_t face_id, std::size_t k, std::size_t line) {
        if (idx < 0 || std::uint64_t(idx) >= nv) {
            const std::uint64_t tri = tri_id + (k < 3 ? 0 : k - 2);
            fail(file, line,
                 "triangle " + std::to_string(tri) + " (face " + std::to_string(face_id) + ") has vertex index " +
                     std::to_string(idx) + " out of range (" + std::to_string(nv) + " vertices)");
        }
    };

    if (format == Format::ascii) {
        for (const Element& e : elements) {
            const bool is_vert = &e == vert, is_face = &e == face;
            for (std::uint64_t n = 0; n < e.count; ++n) {
                std::string_view l;
                do {
                    if (!lines.next(l))
                        fail(file, lines.line, "unexpected end of file in element '" + e.name + "' (read " +
                                                   std::to_string(n) + " of " + std::to_string(e.count) + ")");
                } while (trim(l).empty());
                Tokens tk(l);
                Vec3 pos;
                for (std::size_t i = 0; i < e.props.size(); ++i) {
                    const Property& p = e.props[i];
                    std::string_view tok;
                    if (!tk.next(tok))
                        fail(file, lines.line, "too few values for element '" + e.name + "' (property " + p.name + ")");
                    if (!p.list) {
                        if (is_vert && (int(i) == ix || int(i) == iy || int(i) == iz)) {
                            float f;
                            if (!parse_float(tok, f)) fail(file, lines.line, "bad number " + quote(tok));
                            (int(i) == ix ? pos.x : int(i) == iy ? pos.y : pos.z) = f;
                        } else if (is_int(p.type)) {
                            std::int64_t v;
                            if (!parse_int(tok, v) || !ascii_int_in_range(v, p.type))
                                fail(file, lines.line, "bad integer " + quote(tok) + " for property " + p.name);
                        } else {
                            double d;
                            if (!parse_double(tok, d)) fail(file, lines.line, "bad number " + quote(tok));
                        }
                        continue;
                    }
                    std::int64_t cnt;
                    if (!parse_int(tok, cnt) || cnt < 0 || !ascii_int_in_range(cnt, p.count_type))
                        fail(file, lines.line, "bad list count " + quote(tok));
                    const bool indices = is_face && int(i) == iface;
                    if (indices) poly.clear();
                    for (std::int64_t k = 0; k < cnt; ++k) {
                        if (!tk.next(tok))
                            fail(file, lines.line, "list " + p.name + " has fewer than " + std::to_string(cnt) + " values");
                        if (is_int(p.type)) {
                            std::int64_t v;
                            if (!parse_int(tok, v) || !ascii_int_in_range(v, p.type))
                                fail(file, lines.line, "bad integer " + quote(tok) + " in list " + p.name);
                            if (indices) {
                                check_index(v, n, std::size_t(k), lines.line);
                                poly.push_back(std::uint32_t(v));
                            }
                        } else {
                            double d;
                            if (!parse_double(tok, d)) fail(file, lines.line, "bad number " + quote(tok));
                        }
                    }
                    if (indices) add_face(n, lines.line);
                }
                if (!tk.empty_rest())
                    fail(file, lines.line, "too many values for element '" + e.name + "'");
                if (is_vert) mesh.positions.push_back(pos);
            }
        }
        std::string_view l;
        while (lines.next(l))
            if (!trim(l).empty()) fail(file, lines.line, "unexpected data after the last element");
    } else {
        Binary bin{reinterpret_cast<const unsigned char*>(lines.p), reinterpret_cast<const unsigned char*>(lines.end),
                   (format == Format::binary_be) != (std::endian::native == std::endian::big)};
        auto need = [&](std::size_t bytes, const Element& e, std::uint64_t n) {
            if (std::size_t(bin.end - bin.p) < bytes)
                fail(file, 0, "truncated: data ends in element '" + e.name + "' " + std::to_string(n) + " of " +
                                  std::to_string(e.count));
        };
        for (const Element& e : elements) {
            const bool is_vert = &e == vert, is_face = &e == face;
            for (std::uint64_t n = 0; n < e.count; ++n) {
                Vec3 pos;
                for (std::size_t i = 0; i < e.props.size(); ++i) {
                    const Property& p = e.props[i];
                    if (!p.list) {
                        need(type_size(p.type), e, n);
                        if (is_vert && (int(i) == ix || int(i) == iy || int(i) == iz))
                            (int(i) == ix ? pos.x : int(i) == iy ? pos.y : pos.z) = bin.as_float(p.type);
                        else
                            bin.p += type_size(p.type);
                        continue;
                    }
                    need(type_size(p.count_type), e, n);
                    const std::int64_t cnt = bin.as_int(p.count_type);
                    if (cnt < 0) fail(file, 0, "negative list count in element '" + e.name + "' " + std::to_string(n));
                    if (std::uint64_t(cnt) > std::size_t(bin.end - bin.p) / type_size(p.type)) need(~std::size_t(0), e, n);
                    if (is_face && int(i) == iface) {
                        poly.clear();
                        for (std::int64_t k = 0; k < cnt; ++k) {
                            const std::int64_t v = bin.as_int(p.type);
                            check_index(v, n, std::size_t(k), 0);
                            poly.push_back(std::uint32_t(v));
                        }
                        add_face(n, 0);
                    } else {
                        bin.p += std::size_t(cnt) * type_size(p.type);
                    }
                }
                if (is_vert) mesh.positions.push_back(pos);
            }
        }
        if (bin.p != bin.end)
            fail(file, 0, std::to_string(bin.end - bin.p) + " unexpected bytes after the last element");
    }
    return mesh;
}

}  // namespace simdbvh::scene::detail
