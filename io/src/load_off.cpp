// OFF (also COFF/NOFF/CNOFF headers): "OFF", then "nv nf ne", nv vertex lines
// (x y z, extra numbers such as colours allowed), nf face lines
// ("n i0 .. in-1", optional colour numbers). '#' starts a comment.
#include <algorithm>

#include "simdbvh/io/internal/text.h"

namespace simdbvh::io::detail {

Mesh load_off(const std::string& file, const std::vector<char>& data) {
    const std::size_t start = check_text(file, data);
    Lines lines(data.data() + start, data.data() + data.size());
    std::string_view line;
    auto next_nonempty = [&](const char* what) {
        std::string_view l;
        for (;;) {
            if (!lines.next(l)) fail(file, lines.line, std::string("unexpected end of file: expected ") + what);
            l = strip_comment(l);
            Tokens t(l);
            if (!t.empty_rest()) return l;
        }
    };
    line = next_nonempty("the OFF header");
    Tokens head(line);
    std::string_view kw;
    head.next(kw);
    if (kw != "OFF" && kw != "COFF" && kw != "NOFF" && kw != "CNOFF")
        fail(file, lines.line, "not an OFF file (header " + quote(kw) + ")");
    std::string_view tok;
    std::int64_t counts[3] = {0, 0, 0};
    int have = 0;
    if (head.next(tok)) {  // counts on the header line
        do {
            if (have == 3 || !parse_int(tok, counts[have]) || counts[have] < 0)
                fail(file, lines.line, "bad count " + quote(tok));
            ++have;
        } while (head.next(tok));
    } else {
        line = next_nonempty("vertex and face counts");
        Tokens t(line);
        while (t.next(tok)) {
            if (have == 3 || !parse_int(tok, counts[have]) || counts[have] < 0)
                fail(file, lines.line, "bad count " + quote(tok));
            ++have;
        }
    }
    if (have < 2) fail(file, lines.line, "expected vertex and face counts");
    const std::uint64_t nv = std::uint64_t(counts[0]), nf = std::uint64_t(counts[1]);
    // Each vertex line needs at least 6 bytes ("0 0 0\n"), each face line 2 ("3\n": a bad face is
    // reported by the face loop, with its line); the last line may lack its newline. Checked
    // before allocating; the reservations never exceed the bytes present.
    const std::uint64_t body = std::uint64_t(lines.end - lines.p) + 1;
    if (nv > body / 6 || nf > (body - nv * 6) / 2)
        fail(file, lines.line,
             "counts (" + std::to_string(nv) + " vertices, " + std::to_string(nf) + " faces) are larger than the " +
                 std::to_string(body - 1) + " bytes that follow");
    if (nv > 0xFFFFFFFFull) fail(file, lines.line, "too many vertices");
    Mesh mesh;
    mesh.positions.reserve(std::size_t(nv));  // <= 2 x body (6 bytes per 12-byte vertex)
    mesh.triangles.reserve(std::size_t(std::min<std::uint64_t>(nf, (body - nv * 6) / 8)));
    for (std::uint64_t i = 0; i < nv; ++i) {
        line = next_nonempty("a vertex");
        Tokens t(line);
        Vec3 p;
        for (int k = 0; k < 3; ++k) {
            if (!t.next(tok)) fail(file, lines.line, "vertex " + std::to_string(i) + " needs 3 coordinates");
            if (!parse_float(tok, (k == 0 ? p.x : k == 1 ? p.y : p.z))) fail(file, lines.line, bad_number(tok));
        }
        while (t.next(tok)) {
            double d;
            if (!parse_double(tok, d)) fail(file, lines.line, "bad number " + quote(tok));
        }
        mesh.positions.push_back(p);
    }
    std::vector<std::uint32_t> poly;
    for (std::uint64_t f = 0; f < nf; ++f) {
        line = next_nonempty("a face");
        Tokens t(line);
        std::int64_t n;
        t.next(tok);
        if (!parse_int(tok, n) || n < 0) fail(file, lines.line, "bad face vertex count " + quote(tok));
        if (n < 3)
            fail(file, lines.line,
                 "face " + std::to_string(f) + " has " + std::to_string(n) + " vertices; at least 3 needed");
        poly.clear();
        for (std::int64_t k = 0; k < n; ++k) {
            std::int64_t idx;
            if (!t.next(tok))
                fail(file, lines.line,
                     "face " + std::to_string(f) + " has fewer than " + std::to_string(n) + " indices");
            if (!parse_int(tok, idx)) fail(file, lines.line, "bad index " + quote(tok));
            if (idx < 0 || std::uint64_t(idx) >= nv) {
                const std::uint64_t tri = mesh.triangles.size() + (k < 3 ? 0 : std::uint64_t(k) - 2);
                fail(file, lines.line,
                     "triangle " + std::to_string(tri) + " (face " + std::to_string(f) + ") has vertex index " +
                         std::to_string(idx) + " out of range (" + std::to_string(nv) + " vertices)");
            }
            poly.push_back(std::uint32_t(idx));
        }
        while (t.next(tok)) {  // optional colour
            double d;
            if (!parse_double(tok, d)) fail(file, lines.line, "bad number " + quote(tok));
        }
        for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
            if (mesh.triangles.size() >= kMaxTriangles - 1) fail(file, lines.line, "too many triangles");
            mesh.triangles.push_back(Triangle{poly[0], poly[k], poly[k + 1]});
        }
    }
    std::string_view l;
    while (lines.next(l))
        if (!Tokens(strip_comment(l)).empty_rest()) fail(file, lines.line, "unexpected data after the last face");
    return mesh;
}

}  // namespace simdbvh::io::detail
