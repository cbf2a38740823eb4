// PLY header: "ply", format, element / property lines, end_header.
#include "ply.h"

namespace simdbvh::io::detail::ply {
namespace {

bool parse_type(std::string_view s, Type& t) {
    struct Name {
        const char* n;
        Type t;
    };
    static const Name names[] = {
        {"char", Type::i8},   {"int8", Type::i8},     {"uchar", Type::u8},   {"uint8", Type::u8},
        {"short", Type::i16}, {"int16", Type::i16},   {"ushort", Type::u16}, {"uint16", Type::u16},
        {"int", Type::i32},   {"int32", Type::i32},   {"uint", Type::u32},   {"uint32", Type::u32},
        {"float", Type::f32}, {"float32", Type::f32}, {"double", Type::f64}, {"float64", Type::f64},
    };
    for (const Name& n : names)
        if (s == n.n) {
            t = n.t;
            return true;
        }
    return false;
}

std::string_view trim(std::string_view s) {
    while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
    while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
    return s;
}

void parse_format(const std::string& file, std::size_t line, Tokens& tk, Format& format) {
    std::string_view f, ver;
    if (!tk.next(f) || !tk.next(ver) || !tk.empty_rest()) fail(file, line, "malformed format line");
    if (f == "ascii") format = Format::ascii;
    else if (f == "binary_little_endian") format = Format::binary_le;
    else if (f == "binary_big_endian") format = Format::binary_be;
    else fail(file, line, "unknown PLY format " + quote(f));
    if (ver != "1.0") fail(file, line, "unsupported PLY version " + quote(ver));
}

Element parse_element(const std::string& file, std::size_t line, Tokens& tk) {
    std::string_view name, count;
    std::int64_t n = 0;
    if (!tk.next(name) || !tk.next(count) || !tk.empty_rest()) fail(file, line, "malformed element line");
    if (!parse_int(count, n) || n < 0) fail(file, line, "bad element count " + quote(count));
    return Element{std::string(name), std::uint64_t(n), line, {}};
}

Property parse_property(const std::string& file, std::size_t line, Tokens& tk) {
    Property prop;
    std::string_view a, b, c, name;
    if (!tk.next(a)) fail(file, line, "malformed property line");
    if (a == "list") {
        if (!tk.next(b) || !tk.next(c) || !tk.next(name) || !tk.empty_rest())
            fail(file, line, "malformed list property line");
        prop.list = true;
        if (!parse_type(b, prop.count_type) || !is_int(prop.count_type))
            fail(file, line, "bad list count type " + quote(b));
        if (!parse_type(c, prop.type)) fail(file, line, "unknown property type " + quote(c));
    } else {
        if (!tk.next(name) || !tk.empty_rest()) fail(file, line, "malformed property line");
        if (!parse_type(a, prop.type)) fail(file, line, "unknown property type " + quote(a));
    }
    prop.name = std::string(name);
    return prop;
}

}  // namespace

std::size_t type_size(Type t) {
    switch (t) {
    case Type::i8:
    case Type::u8: return 1;
    case Type::i16:
    case Type::u16: return 2;
    case Type::i32:
    case Type::u32:
    case Type::f32: return 4;
    case Type::f64: return 8;
    }
    return 1;
}

std::optional<Header> parse_header(const std::string& file, const char* data, std::size_t size) {
    const std::size_t bom = size >= 3 && std::string_view(data, 3) == "\xEF\xBB\xBF" ? 3 : 0;
    Lines lines(data + bom, data + size);
    std::string_view line;
    if (!lines.next(line) || trim(line) != "ply") fail(file, 1, "not a PLY file (first line must be 'ply')");
    Header h;
    bool have_format = false;
    while (lines.next(line)) {
        Tokens tk(line);
        std::string_view kw;
        if (!tk.next(kw)) continue;
        if (kw == "end_header") {
            if (!tk.empty_rest()) fail(file, lines.line, "junk after end_header");
            if (!have_format) fail(file, 0, "header has no format line");
            h.body = std::size_t(lines.p - data);
            h.lines = lines.line;
            return h;
        }
        if (kw == "format") {
            parse_format(file, lines.line, tk, h.format);
            have_format = true;
        } else if (kw == "element") {
            h.elements.push_back(parse_element(file, lines.line, tk));
        } else if (kw == "property") {
            if (h.elements.empty()) fail(file, lines.line, "property before any element");
            h.elements.back().props.push_back(parse_property(file, lines.line, tk));
        }
        // comment, obj_info and any other header line (e.g. Blender 2.4's "Created by Blender3D ...") are skipped.
    }
    return std::nullopt;
}

int face_list(const std::string& file, const Element& e) {
    int iface = -1;
    for (std::size_t i = 0; i < e.props.size(); ++i) {
        const Property& p = e.props[i];
        if (p.name != "vertex_indices" && p.name != "vertex_index") continue;
        if (!p.list || !is_int(p.type)) fail(file, e.header_line, p.name + " must be a list of integers");
        if (iface >= 0) fail(file, e.header_line, "two vertex index lists");
        iface = int(i);
    }
    return iface;
}

}  // namespace simdbvh::io::detail::ply
