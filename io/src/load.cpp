// load_mesh: picks the parser and size limit by extension, reads the file
// (read_file.cpp), then applies the shared finiteness checks.
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <new>
#include <stdexcept>
#include <system_error>

#include "simdbvh/io/internal/size_limit.h"

namespace simdbvh::io::detail {

void fail(const std::string& file, std::size_t line, const std::string& problem) {
    if (line) throw Error(printable(file) + ":" + std::to_string(line) + ": " + problem);
    throw Error(printable(file) + ": " + problem);
}

std::string printable(std::string_view s, std::size_t max) {
    std::string out;
    const std::size_t n = std::min(s.size(), max);
    for (std::size_t i = 0; i < n; ++i) {
        const unsigned char c = static_cast<unsigned char>(s[i]);
        if (c >= 0x20 && c < 0x7f) {
            out += char(c);
        } else {
            static const char* hex = "0123456789abcdef";
            out += "\\x";
            out += hex[c >> 4];
            out += hex[c & 15];
        }
    }
    if (s.size() > n) out += "...";
    return out;
}

std::string quote(std::string_view s) { return "'" + printable(s, 40) + "'"; }

static bool strip_plus(std::string_view& tok) {
    if (!tok.empty() && tok[0] == '+') {
        tok.remove_prefix(1);
        if (tok.empty() || tok[0] == '-' || tok[0] == '+') return false;
    }
    return !tok.empty();
}

bool parse_float(std::string_view tok, float& out) {
    if (!strip_plus(tok)) return false;
    float v = 0;
    auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v, std::chars_format::general);
    if (ptr != tok.data() + tok.size()) return false;
    if (ec == std::errc::result_out_of_range) {
        // Overflow is an error; underflow gives strtof's (correctly rounded) result.
        std::string s(tok);
        errno = 0;
        v = std::strtof(s.c_str(), nullptr);
        if (std::isinf(v)) return false;
    } else if (ec != std::errc()) {
        return false;
    }
    out = v;
    return true;
}

bool parse_double(std::string_view tok, double& out) {
    if (!strip_plus(tok)) return false;
    double v = 0;
    auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v, std::chars_format::general);
    if (ptr != tok.data() + tok.size()) return false;
    if (ec == std::errc::result_out_of_range) {
        std::string s(tok);
        v = std::strtod(s.c_str(), nullptr);
        if (std::isinf(v)) return false;
    } else if (ec != std::errc()) {
        return false;
    }
    out = v;
    return true;
}

std::string bad_number(std::string_view tok) {
    double d = 0;
    std::string_view t = tok;
    if (strip_plus(t)) {
        auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), d, std::chars_format::general);
        const bool whole = ptr == t.data() + t.size();
        const bool huge = ec == std::errc::result_out_of_range
                              ? std::isinf(std::strtod(std::string(t).c_str(), nullptr))
                              : ec == std::errc() && std::isinf(float(d)) && std::isfinite(d);
        if (whole && huge) return "number " + quote(tok) + " is out of float range";
    }
    return "bad number " + quote(tok);
}

bool parse_int(std::string_view tok, std::int64_t& out) {
    if (!strip_plus(tok)) return false;
    auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), out);
    return ec == std::errc() && ptr == tok.data() + tok.size();
}

std::size_t check_text(const std::string& file, const std::vector<char>& data) {
    const auto* u = reinterpret_cast<const unsigned char*>(data.data());
    const std::size_t n = data.size();
    if (n >= 2 && ((u[0] == 0xFE && u[1] == 0xFF) || (u[0] == 0xFF && u[1] == 0xFE)))
        fail(file, 0, "UTF-16/UTF-32 text is not supported (byte order mark)");
    const void* nul = n ? std::memchr(data.data(), 0, n) : nullptr;
    if (nul) {
        const char* at = static_cast<const char*>(nul);
        const std::size_t line = 1 + std::size_t(std::count(data.data(), at, '\n'));
        fail(file, line, "NUL byte in a text file (binary data or UTF-16 text)");
    }
    if (n >= 3 && u[0] == 0xEF && u[1] == 0xBB && u[2] == 0xBF) return 3;
    return 0;
}

void finish(const std::string& file, Mesh& mesh, const LoadOptions& opts, LoadReport* report) {
    if (mesh.triangles.size() >= kMaxTriangles)
        fail(file, 0, std::to_string(mesh.triangles.size()) + " triangles > max " + std::to_string(kMaxTriangles - 1));
    std::size_t bad = 0, first = 0;
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        if (!is_finite(mesh.positions[i])) {
            if (bad++ == 0) first = i;
        }
    }
    if (report) *report = LoadReport{};
    if (!bad) return;
    if (!opts.drop_invalid)
        fail(file, 0,
             std::to_string(bad) + (bad == 1 ? " vertex is" : " vertices are") + " NaN or infinite (first: vertex " +
                 std::to_string(first) + ")");
    std::size_t kept = 0;
    for (const Triangle& t : mesh.triangles) {
        if (is_finite(mesh.positions[t[0]]) && is_finite(mesh.positions[t[1]]) && is_finite(mesh.positions[t[2]]))
            mesh.triangles[kept++] = t;
    }
    if (report) report->dropped_triangles = mesh.triangles.size() - kept;
    mesh.triangles.resize(kept);
}

}  // namespace simdbvh::io::detail

namespace simdbvh::io {

namespace {

struct Format {
    Mesh (*parse)(const std::string&, const std::vector<char>&);
    detail::SizeLimit limit;
};

Format format_of(const std::filesystem::path& path) {
    using namespace detail;
    auto lower = [](std::string s) {
        for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
        return s;
    };
    std::string ext = lower(path.extension().string());
    if (ext == ".gz") ext = lower(path.stem().extension().string());
    if (ext == ".ply") return {load_ply, ply_limit};
    if (ext == ".obj") return {load_obj, obj_limit};
    if (ext == ".stl") return {load_stl, stl_limit};
    if (ext == ".off") return {load_off, off_limit};
    fail(path.string(), 0,
         "unknown mesh format " + quote(ext.empty() ? std::string("(none)") : ext) +
             " (expected .ply, .obj, .stl or .off, optionally .gz)");
}

}  // namespace

Mesh load_mesh(const std::filesystem::path& path, const LoadOptions& opts, LoadReport* report) {
    using namespace detail;
    const std::string file = path.string();
    const Format format = format_of(path);
    try {
        const std::vector<char> data = read_file(path, format.limit);
        if (data.empty()) fail(file, 0, "file is empty (0 bytes)");
        Mesh mesh = format.parse(file, data);
        finish(file, mesh, opts, report);
        return mesh;
    } catch (const std::bad_alloc&) {
        fail(file, 0, "out of memory while loading (the file or the mesh it declares does not fit)");
    } catch (const std::length_error&) {
        fail(file, 0, "out of memory while loading (the file or the mesh it declares does not fit)");
    }
}

}  // namespace simdbvh::io
