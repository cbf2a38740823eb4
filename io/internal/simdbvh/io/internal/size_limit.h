#pragma once
// How large a mesh file's (decompressed) data may grow, decided by its format
// from the first bytes: read_file stops with an error past that, so memory is
// bounded by what the header honestly declares.
//   binary STL: exactly 84 + 50 n (n from the header).
//   PLY: header + per element count x (binary: scalar sizes, lists of up to
//        255 items on average; ASCII: 32 bytes per value), + 16 MiB slack.
//   OFF: header + 1 KiB per vertex line + 8 KiB per face line, + 16 MiB slack.
//   OBJ, ASCII STL (no counts) and every text format: at most kMaxTextBytes
//        (64 GiB) and at most the machine's physical memory.
//   A JSON scene: at most kMaxJsonBytes (4 GiB) and at most the physical
//        memory (its document takes several times the text).
// Text formats are also checked for NUL bytes chunk by chunk (fail fast).
#include <cstdint>
#include <functional>
#include <optional>
#include <string_view>

#include "simdbvh/io/internal/text.h"

namespace simdbvh::io::detail {

struct Allowance {
    std::uint64_t max_bytes = 0;
    bool text = false;  // NUL bytes are an error
    std::string why;    // for the message: "the header's counts allow"
};

// Called with the data read so far (a prefix; `complete` when it is the whole
// file) until it returns an allowance; throws Error when the prefix shows the
// file is not of the format; nullopt while the prefix is too short to tell.
using SizeLimit =
    std::function<std::optional<Allowance>(const std::string& file, std::string_view prefix, bool complete)>;

inline constexpr std::uint64_t kMaxTextBytes = std::uint64_t(64) << 30;
inline constexpr std::uint64_t kMaxJsonBytes = std::uint64_t(4) << 30;
inline constexpr std::uint64_t kSlackBytes = std::uint64_t(16) << 20;

// min(kMaxTextBytes, physical memory).
std::uint64_t text_cap();
std::uint64_t sat_add(std::uint64_t a, std::uint64_t b);
std::uint64_t sat_mul(std::uint64_t a, std::uint64_t b);
// Skips a UTF-8 byte order mark.
std::size_t bom_size(std::string_view s);

std::optional<Allowance> ply_limit(const std::string& file, std::string_view prefix, bool complete);
std::optional<Allowance> stl_limit(const std::string& file, std::string_view prefix, bool complete);
std::optional<Allowance> off_limit(const std::string& file, std::string_view prefix, bool complete);
std::optional<Allowance> obj_limit(const std::string& file, std::string_view prefix, bool complete);
std::optional<Allowance> json_limit(const std::string& file, std::string_view prefix, bool complete);

// Reads a regular file (symlinks followed; devices, FIFOs, sockets and
// folders refused), gzip (by magic bytes, whatever the name; concatenated
// members allowed, any other trailing bytes an error) or raw, within `limit`.
std::vector<char> read_file(const std::filesystem::path& file, const SizeLimit& limit);

}  // namespace simdbvh::io::detail
