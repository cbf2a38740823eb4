// OBJ: "v x y z [w]" (optional vertex colours "v x y z r g b") and
// "f a b c ..." with v, v/vt, v//vn or v/vt/vn references; negative indices
// are relative to the vertices defined so far. Polygons are fan-triangulated
// in order. Every other statement is ignored.
#include "simdbvh/io/internal/text.h"

namespace simdbvh::io::detail {

Mesh load_obj(const std::string& file, const std::vector<char>& data) {
    const std::size_t start = check_text(file, data);
    Lines lines(data.data() + start, data.data() + data.size());
    Mesh mesh;
    // No counts up front: vectors grow with the data actually present.
    std::vector<std::uint32_t> poly;
    std::string_view line;
    std::uint64_t face_id = 0;
    while (lines.next(line)) {
        Tokens tk(strip_comment(line));
        std::string_view kw;
        if (!tk.next(kw)) continue;
        if (kw == "v") {
            float c[3];
            std::string_view tok;
            for (float& x : c) {
                if (!tk.next(tok)) fail(file, lines.line, "vertex needs 3 coordinates");
                if (!parse_float(tok, x)) fail(file, lines.line, bad_number(tok));
            }
            int extra = 0;
            while (tk.next(tok)) {
                double d;
                if (!parse_double(tok, d)) fail(file, lines.line, "bad number " + quote(tok));
                ++extra;
            }
            if (extra != 0 && extra != 1 && extra != 3 && extra != 4)
                fail(file, lines.line, "vertex has " + std::to_string(3 + extra) + " values (expected 3, 4, 6 or 7)");
            if (mesh.positions.size() >= 0xFFFFFFFFull) fail(file, lines.line, "too many vertices");
            mesh.positions.push_back(Vec3{c[0], c[1], c[2]});
        } else if (kw == "f") {
            poly.clear();
            std::string_view tok;
            const std::int64_t nv = std::int64_t(mesh.positions.size());
            while (tk.next(tok)) {
                const std::string_view ref = tok.substr(0, tok.find('/'));
                // The vt and vn parts must be integers (or empty) too: junk is an error.
                std::string_view rest = tok.substr(ref.size());
                int slashes = 0;
                while (!rest.empty()) {
                    rest.remove_prefix(1);
                    if (++slashes > 2) fail(file, lines.line, "bad face vertex " + quote(tok));
                    const std::string_view part = rest.substr(0, rest.find('/'));
                    std::int64_t dummy;
                    if (!part.empty() && !parse_int(part, dummy))
                        fail(file, lines.line, "bad face vertex " + quote(tok));
                    if (part.empty() && slashes == 2 && rest.empty())
                        fail(file, lines.line, "bad face vertex " + quote(tok));
                    rest.remove_prefix(part.size());
                }
                std::int64_t idx;
                if (!parse_int(ref, idx)) fail(file, lines.line, "bad face vertex " + quote(tok));
                const std::int64_t abs = idx < 0 ? nv + idx : idx - 1;
                if (idx == 0 || abs < 0 || abs >= nv) {
                    const std::size_t k = poly.size();
                    const std::uint64_t tri = mesh.triangles.size() + (k < 3 ? 0 : k - 2);
                    fail(file, lines.line,
                         "triangle " + std::to_string(tri) + " (face " + std::to_string(face_id) +
                             ") has vertex index " + std::to_string(idx) + " out of range (" + std::to_string(nv) +
                             " vertices defined so far)");
                }
                poly.push_back(std::uint32_t(abs));
            }
            if (poly.size() < 3)
                fail(file, lines.line,
                     "face " + std::to_string(face_id) + " has " + std::to_string(poly.size()) +
                         " vertices; at least 3 needed");
            for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
                if (mesh.triangles.size() >= kMaxTriangles - 1) fail(file, lines.line, "too many triangles");
                mesh.triangles.push_back(Triangle{poly[0], poly[k], poly[k + 1]});
            }
            ++face_id;
        }
        // vt, vn, vp, g, o, s, usemtl, mtllib, l, p, ...: ignored.
    }
    return mesh;
}

}  // namespace simdbvh::io::detail
