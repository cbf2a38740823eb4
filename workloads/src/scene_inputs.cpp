// scene_input_files: the files behind a scene name, found the way the loaders
// (scenes.cpp, scene_builtin.cpp, scene_json.cpp) resolve names.
#include "simdbvh/workloads/scene_inputs.h"

#include <algorithm>
#include <charconv>
#include <set>
#include <system_error>
#include <vector>

#include <nlohmann/json.hpp>

#include "simdbvh/workloads/scene_desc.h"
#include "simdbvh/workloads/scenes.h"
#include "simdbvh/io/internal/size_limit.h"

namespace simdbvh::workloads {
namespace {

namespace fs = std::filesystem;

// "base" or "base-N", N decimal digits (the procedural names of load_scene).
bool procedural(std::string_view s) {
    if (s == "terrain") return true;
    for (std::string_view base : {"icosphere", "soup"}) {
        if (s.substr(0, base.size()) != base) continue;
        std::string_view rest = s.substr(base.size());
        if (rest.empty()) return true;
        if (rest[0] != '-' || rest.size() == 1) continue;
        std::uint64_t v = 0;
        auto [p, ec] = std::from_chars(rest.data() + 1, rest.data() + rest.size(), v);
        if (ec == std::errc() && p == rest.data() + rest.size()) return true;
    }
    return false;
}

bool is_cached_name(std::string_view s) {
    const std::vector<std::string> names = scene_names();
    return !procedural(s) && std::find(names.begin(), names.end(), s) != names.end();
}

std::string chain(const std::string& via, const std::string& step) { return via.empty() ? step : via + " -> " + step; }

class Collector {
public:
    std::vector<SceneInput> out;

    // What load_scene(name) reads.
    void mesh(std::string_view name, const std::string& via) {
        if (procedural(name)) return;
        if (is_cached_name(name)) {
            // Not cached: loading fails before anything is written.
            if (const auto file = cached_scene_file(name))
                add(*file, chain(via, "the cache file of '" + std::string(name) + "'"));
            return;
        }
        const fs::path p{std::string(name)};
        if (p.extension() == ".json") return json(p, via);
        add(p, via);
    }

    // What load_scene_desc(name) reads (a top-level name: JSON mesh references go to load_scene).
    void desc(std::string_view name, const std::string& via) {
        if (is_builtin_scene(name)) {
            if (name == "room") {
                mesh("bunny", via);
                mesh("teapot", via);
            } else if (name.substr(0, 10) == "instances-") {
                mesh("dragon", via);
            }
            return;
        }
        const fs::path p{std::string(name)};
        if (p.extension() == ".json") return json(p, via);
        mesh(name, via);
    }

private:
    void add(const fs::path& p, const std::string& via) {
        for (const SceneInput& s : out)
            if (s.path == p) return;
        out.push_back({p, via});
    }

    // The JSON file and its geometries' mesh references (json_mesh_path: a path relative to the JSON file's
    // folder, or a name for load_scene).
    void json(const fs::path& file, const std::string& via) {
        std::error_code ec;
        const fs::path key = fs::weakly_canonical(file, ec);
        if (!seen_.insert(ec ? file : key).second) return;
        add(file, via);
        std::vector<char> text;  // read as load_scene_json reads it (regular files only, raw or gzip, bounded)
        try {
            text = io::detail::read_file(file, io::detail::json_limit);
        } catch (const std::exception&) {
            return;  // unreadable: loading it fails before any output is written
        }
        const nlohmann::json root =
            nlohmann::json::parse(text.begin(), text.end(), nullptr, /*allow_exceptions=*/false);
        if (!root.is_object() || !root.contains("geometries") || !root["geometries"].is_array()) return;
        const nlohmann::json& geoms = root["geometries"];
        for (std::size_t i = 0; i < geoms.size(); ++i) {
            const nlohmann::json& g = geoms[i];
            if (!g.is_object() || !g.contains("mesh") || !g["mesh"].is_string()) continue;
            const std::string ref = g["mesh"].get<std::string>();
            // The named file's own references need no file name; nested ones do.
            const std::string where = "geometries[" + std::to_string(i) + "].mesh";
            const std::string step = via.empty() ? where : chain(via, file.string() + ": " + where);
            if (const auto path = json_mesh_path(file.parent_path(), ref)) mesh(path->string(), step);
            else mesh(ref, step);
        }
    }

    std::set<fs::path> seen_;
};

}  // namespace

std::vector<SceneInput> scene_input_files(std::string_view name) {
    Collector c;
    c.desc(name, "");
    c.mesh(name, "");  // the mesh commands' reading: "room" there is a file
    return std::move(c.out);
}

}  // namespace simdbvh::workloads
