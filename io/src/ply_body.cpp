// PLY body: ASCII lines or binary records, element by element.
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

#include "ply.h"

namespace simdbvh::io::detail::ply {
namespace {

std::string_view trim(std::string_view s) {
    while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
    while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
    return s;
}

bool ascii_int_in_range(std::int64_t v, Type t) {
    switch (t) {
    case Type::i8: return v >= -128 && v <= 127;
    case Type::u8: return v >= 0 && v <= 255;
    case Type::i16: return v >= -32768 && v <= 32767;
    case Type::u16: return v >= 0 && v <= 65535;
    case Type::i32:
        return v >= std::numeric_limits<std::int32_t>::min() && v <= std::numeric_limits<std::int32_t>::max();
    case Type::u32: return v >= 0 && v <= std::numeric_limits<std::uint32_t>::max();
    default: return true;
    }
}

// A scalar read from binary data: as a double (x, y, z) or an integer (list counts, indices).
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
    double as_double(Type t) {
        switch (t) {
        case Type::f32: return raw<float>();
        case Type::f64: return raw<double>();
        default: return double(as_int(t));
        }
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

// One ASCII value of property p (a coordinate, a checked integer or a checked number).
void ascii_value(const std::string& file, std::size_t line, const Property& p, std::string_view tok, float* coord) {
    if (coord) {
        if (!parse_float(tok, *coord)) fail(file, line, bad_number(tok));
    } else if (is_int(p.type)) {
        std::int64_t v;
        if (!parse_int(tok, v) || !ascii_int_in_range(v, p.type))
            fail(file, line, "bad integer " + quote(tok) + " for property " + p.name);
    } else {
        double d;
        if (!parse_double(tok, d)) fail(file, line, "bad number " + quote(tok));
    }
}

void ascii_list(Builder& b, Lines& lines, Tokens& tk, const Property& p, std::string_view tok, bool indices,
                std::uint64_t n) {
    const std::string& file = b.file;
    std::int64_t cnt;
    if (!parse_int(tok, cnt) || cnt < 0 || !ascii_int_in_range(cnt, p.count_type))
        fail(file, lines.line, "bad list count " + quote(tok));
    if (indices) b.poly.clear();
    for (std::int64_t k = 0; k < cnt; ++k) {
        if (!tk.next(tok))
            fail(file, lines.line, "list " + p.name + " has fewer than " + std::to_string(cnt) + " values");
        if (!is_int(p.type)) {
            ascii_value(file, lines.line, p, tok, nullptr);
            continue;
        }
        std::int64_t v;
        if (!parse_int(tok, v) || !ascii_int_in_range(v, p.type))
            fail(file, lines.line, "bad integer " + quote(tok) + " in list " + p.name);
        if (indices) b.add_index(v, n, std::size_t(k), lines.line);
    }
    if (indices) b.add_face(n, lines.line);
}

void ascii_element(Builder& b, Lines& lines, const Element& e, const Layout& l, std::uint64_t n) {
    const std::string& file = b.file;
    std::string_view line;
    do {
        if (!lines.next(line))
            fail(file, lines.line,
                 "unexpected end of file in element '" + e.name + "' (read " + std::to_string(n) + " of " +
                     std::to_string(e.count) + ")");
    } while (trim(line).empty());
    const bool is_vert = &e == l.vert;
    Tokens tk(line);
    float pos[3] = {0, 0, 0};
    for (std::size_t i = 0; i < e.props.size(); ++i) {
        const Property& p = e.props[i];
        std::string_view tok;
        if (!tk.next(tok))
            fail(file, lines.line, "too few values for element '" + e.name + "' (property " + p.name + ")");
        if (p.list) ascii_list(b, lines, tk, p, tok, &e == l.face && int(i) == l.iface, n);
        else ascii_value(file, lines.line, p, tok, is_vert && l.coord(i) >= 0 ? &pos[l.coord(i)] : nullptr);
    }
    if (!tk.empty_rest()) fail(file, lines.line, "too many values for element '" + e.name + "'");
    if (is_vert) b.mesh.positions.push_back(Vec3{pos[0], pos[1], pos[2]});
}

void parse_ascii(Builder& b, const Header& h, const Layout& l, Lines& lines) {
    for (const Element& e : h.elements)
        for (std::uint64_t n = 0; n < e.count; ++n) ascii_element(b, lines, e, l, n);
    std::string_view rest;
    while (lines.next(rest))
        if (!trim(rest).empty()) fail(b.file, lines.line, "unexpected data after the last element");
}

void binary_element(Builder& b, Binary& bin, const Element& e, const Layout& l, std::uint64_t n) {
    const std::string& file = b.file;
    auto need = [&](std::size_t bytes) {
        if (std::size_t(bin.end - bin.p) < bytes)
            fail(file, 0,
                 "truncated: data ends in element '" + e.name + "' " + std::to_string(n) + " of " +
                     std::to_string(e.count));
    };
    const bool is_vert = &e == l.vert;
    float pos[3] = {0, 0, 0};
    for (std::size_t i = 0; i < e.props.size(); ++i) {
        const Property& p = e.props[i];
        if (!p.list) {
            need(type_size(p.type));
            if (!is_vert || l.coord(i) < 0) {
                bin.p += type_size(p.type);
                continue;
            }
            const double d = bin.as_double(p.type);
            pos[l.coord(i)] = float(d);
            if (std::isfinite(d) && !std::isfinite(pos[l.coord(i)]))
                fail(file, 0,
                     "vertex " + std::to_string(n) + " coordinate " + p.name + " = " + std::to_string(d).substr(0, 12) +
                         "... is out of float range");
            continue;
        }
        need(type_size(p.count_type));
        const std::int64_t cnt = bin.as_int(p.count_type);
        if (cnt < 0) fail(file, 0, "negative list count in element '" + e.name + "' " + std::to_string(n));
        if (std::uint64_t(cnt) > std::size_t(bin.end - bin.p) / type_size(p.type)) need(~std::size_t(0));
        if (&e != l.face || int(i) != l.iface) {
            bin.p += std::size_t(cnt) * type_size(p.type);
            continue;
        }
        b.poly.clear();
        for (std::int64_t k = 0; k < cnt; ++k) b.add_index(bin.as_int(p.type), n, std::size_t(k), 0);
        b.add_face(n, 0);
    }
    if (is_vert) b.mesh.positions.push_back(Vec3{pos[0], pos[1], pos[2]});
}

void parse_binary(Builder& b, const Header& h, const Layout& l, const char* begin, const char* end) {
    Binary bin{reinterpret_cast<const unsigned char*>(begin), reinterpret_cast<const unsigned char*>(end),
               (h.format == Format::binary_be) != (std::endian::native == std::endian::big)};
    for (const Element& e : h.elements)
        for (std::uint64_t n = 0; n < e.count; ++n) binary_element(b, bin, e, l, n);
    if (bin.p != bin.end) fail(b.file, 0, std::to_string(bin.end - bin.p) + " unexpected bytes after the last element");
}

}  // namespace

Mesh parse_body(const std::string& file, const Header& h, const Layout& l, const char* begin, const char* end,
                std::size_t line0) {
    Builder b{file, l.nv, {}, 0, {}};
    // Reserved from the counts, but never more than the bytes present (counts were checked against them).
    const std::uint64_t body = std::uint64_t(end - begin);
    b.mesh.positions.reserve(std::size_t(std::min<std::uint64_t>(l.nv, body / sizeof(Vec3))));
    if (l.face) b.mesh.triangles.reserve(std::size_t(std::min<std::uint64_t>(l.face->count, body / sizeof(Triangle))));
    if (h.format == Format::ascii) {
        Lines lines(begin, end);
        lines.line = line0;
        parse_ascii(b, h, l, lines);
    } else {
        parse_binary(b, h, l, begin, end);
    }
    return std::move(b.mesh);
}

}  // namespace simdbvh::io::detail::ply
