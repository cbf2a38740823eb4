#pragma once
// Private helpers shared by the loaders: a line/token cursor that tracks line numbers, exact number parsing
// (std::from_chars) and error construction.
#include <charconv>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "simdbvh/kernels/error.h"
#include "simdbvh/kernels/mesh.h"
#include "simdbvh/io/load.h"

namespace simdbvh::io::detail {

// Errors: "<file>:<line>: <problem>" or "<file>: <problem>" (line 0), the
// file name made printable.
[[noreturn]] void fail(const std::string& file, std::size_t line, const std::string& problem);

// Text from the input (a file name, a key, a token) for a message: every byte
// outside printable ASCII (control characters such as ESC, DEL, non-ASCII)
// as \xNN, so a terminal is never sent an escape sequence; cut after `max`
// bytes of the input with "...".
std::string printable(std::string_view s, std::size_t max = std::string_view::npos);
// printable(s, 40) in single quotes.
std::string quote(std::string_view s);

// A text cursor over [p, end): splits lines (LF, CRLF or CR) and tokens.
struct Lines {
    const char* p;
    const char* end;
    std::size_t line = 0;  // number of the line last returned by next()

    Lines(const char* b, const char* e) : p(b), end(e) {}
    bool at_end() const { return p >= end; }
    // The next line without its terminator; false at the end of the data.
    bool next(std::string_view& out) {
        if (p >= end) return false;
        const char* b = p;
        while (p < end && *p != '\n' && *p != '\r') ++p;
        out = std::string_view(b, std::size_t(p - b));
        if (p < end) {
            if (*p == '\r' && p + 1 < end && p[1] == '\n') ++p;
            ++p;
        }
        ++line;
        return true;
    }
};

inline bool is_space(char c) { return c == ' ' || c == '\t' || c == '\f' || c == '\v'; }

// Splits a line into whitespace-separated tokens.
struct Tokens {
    std::string_view s;
    std::size_t i = 0;
    explicit Tokens(std::string_view line) : s(line) {}
    bool next(std::string_view& tok) {
        while (i < s.size() && is_space(s[i])) ++i;
        if (i >= s.size()) return false;
        std::size_t b = i;
        while (i < s.size() && !is_space(s[i])) ++i;
        tok = s.substr(b, i - b);
        return true;
    }
    bool empty_rest() {
        while (i < s.size() && is_space(s[i])) ++i;
        return i >= s.size();
    }
};

// Exact float parse of a whole token (correctly rounded, == strtof); a
// leading '+' is accepted. Returns false for anything that is not exactly a
// number or whose value overflows float; underflow gives strtof's result.
bool parse_float(std::string_view tok, float& out);
bool parse_double(std::string_view tok, double& out);
// "bad number '<tok>'", or "number '<tok>' is out of float range" for a
// number too large for float (e.g. 1e300).
std::string bad_number(std::string_view tok);
// Whole-token integer parse (a leading '+' is accepted).
bool parse_int(std::string_view tok, std::int64_t& out);

// Strips a '#' comment.
inline std::string_view strip_comment(std::string_view line) {
    std::size_t h = line.find('#');
    return h == std::string_view::npos ? line : line.substr(0, h);
}

// Text formats: reject UTF-16/32 (BOM or NUL bytes near the start), skip a UTF-8 BOM.
// Returns the offset of the first byte of text.
std::size_t check_text(const std::string& file, const std::vector<char>& data);

// Post-load checks shared by every format: vertex finiteness (strict: error
// with the count and first index; drop_invalid: triangles using a non-finite
// vertex are dropped and counted). Indices are checked by the parsers, which
// know the line or face.
void finish(const std::string& file, Mesh& mesh, const LoadOptions& opts, LoadReport* report);

Mesh load_ply(const std::string& file, const std::vector<char>& data);
Mesh load_obj(const std::string& file, const std::vector<char>& data);
Mesh load_stl(const std::string& file, const std::vector<char>& data);
Mesh load_off(const std::string& file, const std::vector<char>& data);

}  // namespace simdbvh::io::detail
