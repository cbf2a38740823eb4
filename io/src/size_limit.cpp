// Per-format size limits (see size_limit.h): decided from the first bytes.
#include "simdbvh/io/internal/size_limit.h"

#include <algorithm>

#include "ply.h"
#include "simdbvh/platform/internal/platform.h"

namespace simdbvh::io::detail {
namespace {

constexpr std::uint64_t kAsciiValueBytes = 32;  // one number and its separator, on average
constexpr std::uint64_t kListItems = 255;       // list length on average (the uchar maximum)
constexpr std::size_t kMaxHeaderBytes = std::size_t(16) << 20;

const char* const kTextWhy = "a text mesh may have (64 GiB or the physical memory, whichever is smaller)";

Allowance text_allowance() { return Allowance{text_cap(), true, kTextWhy}; }

// The prefix up to its last line end (all of it when complete).
std::string_view whole_lines(std::string_view prefix, bool complete) {
    if (complete) return prefix;
    const std::size_t eol = prefix.find_last_of("\r\n");
    return prefix.substr(0, eol == std::string_view::npos ? 0 : eol + 1);
}

bool iequal5(std::string_view a, const char* b) {
    for (std::size_t i = 0; i < 5; ++i)
        if (char(a[i] | 0x20) != b[i]) return false;
    return true;
}

bool has_control_byte(std::string_view s) {
    for (char ch : s) {
        const auto c = static_cast<unsigned char>(ch);
        if (c < 0x20 && c != '\n' && c != '\r' && c != '\t' && c != '\f' && c != '\v') return true;
    }
    return false;
}

std::uint64_t ply_element_bytes(const ply::Element& e, ply::Format format) {
    std::uint64_t per = 0;
    for (const ply::Property& p : e.props) {
        if (format == ply::Format::ascii) per += kAsciiValueBytes * (p.list ? 1 + kListItems : 1);
        else
            per += p.list ? ply::type_size(p.count_type) + kListItems * ply::type_size(p.type) : ply::type_size(p.type);
    }
    return per;
}

}  // namespace

std::uint64_t sat_add(std::uint64_t a, std::uint64_t b) { return a + b < a ? ~std::uint64_t(0) : a + b; }
std::uint64_t sat_mul(std::uint64_t a, std::uint64_t b) {
    std::uint64_t r;
    return __builtin_mul_overflow(a, b, &r) ? ~std::uint64_t(0) : r;
}

std::uint64_t text_cap() {
    const std::uint64_t memory = platform::physical_memory_bytes();
    return memory == 0 ? kMaxTextBytes : std::min(kMaxTextBytes, memory);
}

std::size_t bom_size(std::string_view s) { return s.substr(0, 3) == "\xEF\xBB\xBF" ? 3 : 0; }

std::optional<Allowance> ply_limit(const std::string& file, std::string_view prefix, bool complete) {
    const std::string_view lines = whole_lines(prefix, complete);
    const std::optional<ply::Header> h =
        ply::parse_header(file, lines.data(), lines.size());  // throws "not a PLY file"
    if (!h) {
        if (complete) return Allowance{prefix.size(), false, ""};  // the parser reports the missing end_header
        if (prefix.size() > kMaxHeaderBytes) fail(file, 0, "no end_header in the first 16 MiB (header too long)");
        return std::nullopt;
    }
    std::uint64_t total = sat_add(h->body, kSlackBytes);
    for (const ply::Element& e : h->elements) total = sat_add(total, sat_mul(e.count, ply_element_bytes(e, h->format)));
    if (h->format == ply::Format::ascii)
        return Allowance{std::min(total, text_cap()), true, "the PLY header's element counts allow"};
    return Allowance{total, false, "the PLY header's element counts allow"};
}

std::optional<Allowance> stl_limit(const std::string& file, std::string_view prefix, bool complete) {
    if (prefix.size() < 84 && !complete) return std::nullopt;
    std::size_t i = bom_size(prefix);
    while (i < prefix.size() && (is_space(prefix[i]) || prefix[i] == '\r' || prefix[i] == '\n')) ++i;
    const bool solid = prefix.size() - i >= 5 && iequal5(prefix.substr(i), "solid");
    if (prefix.size() < 84) return Allowance{prefix.size(), solid, ""};  // all of it is here; the parser decides
    const auto* u = reinterpret_cast<const unsigned char*>(prefix.data());
    const std::uint64_t n =
        std::uint64_t(u[80]) | std::uint64_t(u[81]) << 8 | std::uint64_t(u[82]) << 16 | std::uint64_t(u[83]) << 24;
    if (solid && !has_control_byte(prefix)) return text_allowance();  // ASCII (binary float data has some)
    if (3 * n > 0xFFFFFFFFull)
        fail(file, 0,
             "binary STL header says " + std::to_string(n) + " triangles: their " + std::to_string(3 * n) +
                 " vertices do not fit 32-bit indices (max " + std::to_string(0xFFFFFFFFull / 3) + " triangles)");
    return Allowance{84 + 50 * n, false, "the binary STL header's triangle count (" + std::to_string(n) + ") allows"};
}

std::optional<Allowance> off_limit(const std::string&, std::string_view prefix, bool complete) {
    if (prefix.find('\0') != std::string_view::npos) return text_allowance();  // read_file reports the NUL now
    const std::string_view text = whole_lines(prefix.substr(bom_size(prefix)), complete);
    Lines lines(text.data(), text.data() + text.size());
    std::string_view line, tok;
    std::int64_t counts[2] = {-1, -1};
    int have = 0;
    bool keyword = false;
    while (have < 2 && lines.next(line)) {
        Tokens t(strip_comment(line));
        if (!keyword && t.next(tok)) keyword = true;  // "OFF" (checked by the parser)
        while (have < 2 && t.next(tok))
            if (!parse_int(tok, counts[have++]) || counts[have - 1] < 0)
                return text_allowance();  // the parser reports it
    }
    if (have < 2) {
        if (complete || prefix.size() > kMaxHeaderBytes) return text_allowance();
        return std::nullopt;
    }
    std::uint64_t total = sat_add(std::uint64_t(lines.p - text.data()), kSlackBytes);
    total = sat_add(total, sat_mul(std::uint64_t(counts[0]), 1024));
    total = sat_add(total, sat_mul(std::uint64_t(counts[1]), 8192));
    return Allowance{std::min(total, text_cap()), true, "the OFF header's counts allow"};
}

std::optional<Allowance> obj_limit(const std::string&, std::string_view, bool) { return text_allowance(); }

std::optional<Allowance> json_limit(const std::string&, std::string_view, bool) {
    return Allowance{std::min(kMaxJsonBytes, text_cap()), true,
                     "a JSON scene may have (4 GiB or the physical memory, whichever is smaller)"};
}

}  // namespace simdbvh::io::detail
