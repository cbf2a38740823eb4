// Named scenes: npm meshes from the cache (scripts/fetch_scenes.sh) and
// procedural scenes.
#include "simdbvh/workloads/scenes.h"

#include <charconv>
#include <cstdlib>
#include <system_error>

#include "simdbvh/kernels/error.h"
#include "simdbvh/io/load.h"

namespace simdbvh::workloads {
namespace {

struct Cached {
    const char* name;
    const char* file;  // in cache_dir()
};
constexpr Cached kCached[] = {
    {"dragon", "dragon_vrip.ply.gz"},
    {"dragon-res2", "dragon_vrip_res2.ply.gz"},
    {"dragon-res3", "dragon_vrip_res3.ply.gz"},
    {"dragon-res4", "dragon_vrip_res4.ply.gz"},
    {"bunny", "bunny.ply"},
    {"teapot", "teapot.ply"},
};

// "base" or "base-N" with N a non-negative decimal number.
bool match(std::string_view s, std::string_view base, std::optional<std::uint64_t>& n) {
    if (s.substr(0, base.size()) != base) return false;
    s.remove_prefix(base.size());
    n.reset();
    if (s.empty()) return true;
    if (s[0] != '-' || s.size() == 1) return false;
    std::uint64_t v = 0;
    auto [p, ec] = std::from_chars(s.data() + 1, s.data() + s.size(), v);
    if (ec != std::errc() || p != s.data() + s.size()) return false;
    n = v;
    return true;
}

}  // namespace

std::filesystem::path cache_dir() {
    if (const char* env = std::getenv("SIMDBVH_CACHE"); env && *env) return std::filesystem::path(env);
    // The XDG base directory rule, as scripts/fetch_scenes.sh applies it: no path is compiled in, so the
    // installed CLI and the module find the same cache from any folder.
    if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg && xdg[0] == '/')
        return std::filesystem::path(xdg) / "simdbvh" / "scenes";
    if (const char* home = std::getenv("HOME"); home && *home)
        return std::filesystem::path(home) / ".cache" / "simdbvh" / "scenes";
    throw Error("no scene cache: set SIMDBVH_CACHE (or HOME) to the folder scripts/fetch_scenes.sh fills");
}

std::vector<std::string> scene_names() {
    std::vector<std::string> names;
    for (const Cached& c : kCached) names.emplace_back(c.name);
    names.insert(names.end(), {"icosphere", "soup", "terrain"});
    return names;
}

bool is_mesh_name(std::string_view name) {
    for (const Cached& c : kCached)
        if (name == c.name) return true;
    std::optional<std::uint64_t> n;
    return match(name, "icosphere", n) || match(name, "soup", n) || name == "terrain";
}

std::optional<std::filesystem::path> cached_scene_file(std::string_view name) {
    for (const Cached& c : kCached) {
        if (name != c.name) continue;
        std::filesystem::path p = cache_dir() / c.file;
        std::error_code ec;
        if (std::filesystem::is_regular_file(p, ec)) return p;
        return std::nullopt;
    }
    return std::nullopt;
}

bool is_cached(std::string_view name) { return cached_scene_file(name).has_value(); }

Mesh load_scene(std::string_view name) {
    for (const Cached& c : kCached) {
        if (name != c.name) continue;
        if (auto p = cached_scene_file(name)) return io::load_mesh(*p);
        throw Error("scene '" + std::string(name) + "' is not cached (" + (cache_dir() / c.file).string() +
                    " is missing): run scripts/fetch_scenes.sh");
    }
    std::optional<std::uint64_t> n;
    if (match(name, "icosphere", n)) {
        const std::uint64_t level = n.value_or(4);
        if (level > 11) throw Error("scene '" + std::string(name) + "': icosphere level must be 0..11");
        return icosphere(int(level));
    }
    if (match(name, "soup", n)) return random_soup(std::size_t(n.value_or(10000)), 1);
    if (name == "terrain") return terrain();
    return io::load_mesh(std::filesystem::path(std::string(name)));
}

}  // namespace simdbvh::workloads
