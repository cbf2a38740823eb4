// STL: binary (80-byte header, uint32 count, 50 bytes per triangle; detected
// by the size 84 + 50 n, even when the header starts with "solid") and ASCII
// ("solid ... facet normal / outer loop / vertex x3 / endloop / endfacet ...
// endsolid", several solids allowed). Three new vertices per triangle.
#include <bit>
#include <cstring>

#include "simdbvh/io/internal/text.h"

namespace simdbvh::io::detail {
namespace {

bool iequal(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i) {
        char x = a[i], y = b[i];
        if (x >= 'A' && x <= 'Z') x = char(x - 'A' + 'a');
        if (y >= 'A' && y <= 'Z') y = char(y - 'A' + 'a');
        if (x != y) return false;
    }
    return true;
}

// Tokens across lines, with the current line number.
struct Stream {
    const char* p;
    const char* end;
    std::size_t line = 1;
    bool next(std::string_view& tok) {
        for (;;) {
            while (p < end && (is_space(*p) || *p == '\r' || *p == '\n')) {
                if (*p == '\n') ++line;
                ++p;
            }
            if (p >= end) return false;
            const char* b = p;
            while (p < end && !is_space(*p) && *p != '\r' && *p != '\n') ++p;
            tok = std::string_view(b, std::size_t(p - b));
            return true;
        }
    }
    void skip_line() {
        while (p < end && *p != '\n') ++p;
    }
};

float read_le_float(const unsigned char* p) {
    std::uint32_t u =
        std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 | std::uint32_t(p[3]) << 24;
    return std::bit_cast<float>(u);
}

Mesh load_binary(const std::string& file, const std::vector<char>& data, std::uint64_t n) {
    Mesh mesh;
    if (3 * n > 0xFFFFFFFFull)  // vertex indices are uint32
        fail(file, 0,
             std::to_string(n) + " triangles: their " + std::to_string(3 * n) +
                 " vertices do not fit 32-bit indices (max " + std::to_string(0xFFFFFFFFull / 3) + " triangles)");
    mesh.positions.reserve(std::size_t(n) * 3);
    mesh.triangles.reserve(std::size_t(n));
    const auto* p = reinterpret_cast<const unsigned char*>(data.data()) + 84;
    for (std::uint64_t i = 0; i < n; ++i, p += 50) {
        for (int k = 0; k < 3; ++k) {
            const unsigned char* v = p + 12 + 12 * k;
            mesh.positions.push_back(Vec3{read_le_float(v), read_le_float(v + 4), read_le_float(v + 8)});
        }
        const auto b = std::uint32_t(3 * i);
        mesh.triangles.push_back(Triangle{b, b + 1, b + 2});
    }
    return mesh;
}

Mesh load_ascii(const std::string& file, const std::vector<char>& data, std::size_t start) {
    Stream s{data.data() + start, data.data() + data.size()};
    Mesh mesh;
    std::string_view tok;
    auto expect = [&](std::string_view word) {
        if (!s.next(tok)) fail(file, s.line, "unexpected end of file: expected '" + std::string(word) + "'");
        if (!iequal(tok, word)) fail(file, s.line, "expected '" + std::string(word) + "', found " + quote(tok));
    };
    auto number = [&]() {
        float f;
        if (!s.next(tok)) fail(file, s.line, "unexpected end of file: expected a number");
        if (!parse_float(tok, f)) fail(file, s.line, bad_number(tok));
        return f;
    };
    int solids = 0;
    while (s.next(tok)) {
        if (!iequal(tok, "solid")) fail(file, s.line, "expected 'solid', found " + quote(tok));
        ++solids;
        s.skip_line();  // the solid's name
        for (;;) {
            if (!s.next(tok)) fail(file, s.line, "unexpected end of file: expected 'endsolid'");
            if (iequal(tok, "endsolid")) {
                s.skip_line();
                break;
            }
            if (!iequal(tok, "facet")) fail(file, s.line, "expected 'facet' or 'endsolid', found " + quote(tok));
            expect("normal");
            for (int k = 0; k < 3; ++k) number();
            expect("outer");
            expect("loop");
            if (mesh.positions.size() + 3 > 0xFFFFFFFFull)  // vertex indices are uint32
                fail(file, s.line,
                     "too many triangles: more than " + std::to_string(0xFFFFFFFFull / 3) +
                         " (3 vertices each must fit 32-bit indices)");
            const auto b = std::uint32_t(mesh.positions.size());
            for (int v = 0; v < 3; ++v) {
                expect("vertex");
                Vec3 p;
                p.x = number();
                p.y = number();
                p.z = number();
                mesh.positions.push_back(p);
            }
            expect("endloop");
            expect("endfacet");
            mesh.triangles.push_back(Triangle{b, b + 1, b + 2});
        }
    }
    if (!solids) fail(file, 0, "no 'solid' in ASCII STL");
    return mesh;
}

bool all_text(const std::vector<char>& data, std::size_t start) {
    for (std::size_t i = start; i < data.size(); ++i) {
        const char ch = data[i];
        const auto c = static_cast<unsigned char>(ch);
        if (c < 0x20 && c != '\n' && c != '\r' && c != '\t' && c != '\f' && c != '\v') return false;
        if (c >= 0x7f) return false;
    }
    return true;
}

}  // namespace

Mesh load_stl(const std::string& file, const std::vector<char>& data) {
    const std::size_t size = data.size();
    const std::size_t bom = size >= 3 && std::string_view(data.data(), 3) == "\xEF\xBB\xBF" ? 3 : 0;  // UTF-8 BOM
    std::size_t i = bom;
    while (i < size && (is_space(data[i]) || data[i] == '\r' || data[i] == '\n')) ++i;
    const bool solid = size - i >= 5 && iequal(std::string_view(data.data() + i, 5), "solid");
    if (size >= 84) {
        const auto* u = reinterpret_cast<const unsigned char*>(data.data());
        const std::uint64_t n =
            std::uint64_t(u[80]) | std::uint64_t(u[81]) << 8 | std::uint64_t(u[82]) << 16 | std::uint64_t(u[83]) << 24;
        if (84 + 50 * n == size && !(solid && all_text(data, bom))) return load_binary(file, data, n);
        if (!solid)
            fail(file, 0,
                 "binary STL header says " + std::to_string(n) + " triangles (" + std::to_string(84 + 50 * n) +
                     " bytes) but the file has " + std::to_string(size) + " bytes");
    } else if (!solid) {
        fail(file, 0, "not an STL file (" + std::to_string(size) + " bytes, too small for binary, no 'solid')");
    }
    return load_ascii(file, data, check_text(file, data));
}

}  // namespace simdbvh::io::detail
