// PLY: ASCII, binary_little_endian, binary_big_endian. x, y, z picked by name
// from the "vertex" element (any scalar type); faces from the "face" element's
// list "vertex_indices" (or "vertex_index"); everything else is skipped.
// Header: ply_header.cpp; body: ply_body.cpp; here: layout and size check.
#include <algorithm>

#include "ply.h"

namespace simdbvh::io::detail {
namespace {

using namespace ply;

Layout layout(const std::string& file, const Header& h) {
    Layout l;
    for (const Element& e : h.elements) {
        if (e.name == "vertex") {
            if (l.vert) fail(file, e.header_line, "second 'vertex' element");
            l.vert = &e;
            for (std::size_t i = 0; i < e.props.size(); ++i) {
                const Property& p = e.props[i];
                int* slot = p.name == "x" ? &l.ix : p.name == "y" ? &l.iy : p.name == "z" ? &l.iz : nullptr;
                if (!slot) continue;
                if (p.list) fail(file, e.header_line, "vertex property " + p.name + " is a list");
                *slot = int(i);
            }
            if (e.count && (l.ix < 0 || l.iy < 0 || l.iz < 0))
                fail(file, e.header_line, "vertex element lacks x, y or z");
        } else if (e.name == "face") {
            if (l.face) fail(file, e.header_line, "second 'face' element");
            l.face = &e;
            l.iface = face_list(file, e);
        }
    }
    l.nv = l.vert ? l.vert->count : 0;
    if (l.nv > 0xFFFFFFFFull) fail(file, 0, std::to_string(l.nv) + " vertices > max " + std::to_string(0xFFFFFFFFull));
    return l;
}

// The fewest bytes one element can take; a binary face's index list needs 3 items.
// (Reservations are capped by the bytes present in any case: ply_body.cpp.)
std::uint64_t min_bytes(const Element& e, const Layout& l, Format format) {
    std::uint64_t min = 0;
    for (std::size_t i = 0; i < e.props.size(); ++i) {
        const Property& p = e.props[i];
        const std::uint64_t items = &e == l.face && int(i) == l.iface ? 3 : 0;
        if (format == Format::ascii) min += 2;  // lenient: a short line gets its own message, with the line
        else min += p.list ? type_size(p.count_type) + items * type_size(p.type) : type_size(p.type);
    }
    return min;
}

// Counts against the bytes after the header, before allocating anything.
void check_counts(const std::string& file, const Header& h, const Layout& l, std::uint64_t body) {
    std::uint64_t need = 0;
    for (const Element& e : h.elements) {
        const std::uint64_t min = min_bytes(e, l, h.format);
        if (e.count && min == 0)
            fail(file, e.header_line,
                 "element '" + e.name + "' has no properties but count " + std::to_string(e.count));
        if (e.count > (body - std::min(need, body)) / std::max<std::uint64_t>(min, 1))
            fail(file, e.header_line,
                 "element '" + e.name + "' count " + std::to_string(e.count) + " needs at least " +
                     std::to_string(min) + " bytes each but only " + std::to_string(body) +
                     " bytes follow the header (truncated file or wrong count)");
        need += e.count * min;
    }
}

}  // namespace

Mesh load_ply(const std::string& file, const std::vector<char>& data) {
    const std::optional<Header> h = parse_header(file, data.data(), data.size());
    if (!h) fail(file, 0, "truncated header (no end_header)");
    const Layout l = layout(file, *h);
    const std::size_t body = data.size() - h->body;
    check_counts(file, *h, l, body);
    return ply::parse_body(file, *h, l, data.data() + h->body, data.data() + data.size(), h->lines);
}

}  // namespace simdbvh::io::detail
