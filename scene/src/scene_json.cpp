// The JSON scene format (nlohmann-json), strict: every problem is reported
// with its JSON path, e.g. "scene.json: instances[3].transform: singular".
#include <cmath>
#include <limits>
#include <map>
#include <new>
#include <numbers>
#include <set>
#include <vector>
#include <string>

#include <nlohmann/json.hpp>

#include "simdbvh/kernels/error.h"
#include "simdbvh/scene/scene_desc.h"
#include "simdbvh/scene/scenes.h"
#include "size_limit.h"

namespace simdbvh::scene {

namespace {

using Json = nlohmann::json;

struct Parser {
    std::filesystem::path base;

    [[noreturn]] static void fail(const std::string& path, const std::string& what) { throw Error(path + ": " + what); }

    static std::string at(const std::string& path, std::size_t i) { return path + "[" + std::to_string(i) + "]"; }
    static std::string key(const std::string& path, const std::string& k) { return path.empty() ? k : path + "." + k; }

    static void only_keys(const Json& j, const std::string& path, std::initializer_list<const char*> allowed) {
        if (!j.is_object()) fail(path.empty() ? "(root)" : path, "expected an object");
        for (auto it = j.begin(); it != j.end(); ++it) {
            bool ok = false;
            for (const char* a : allowed) ok = ok || it.key() == a;
            if (!ok) fail(key(path, it.key()), "unknown key");
        }
    }
    static const Json& array(const Json& j, const std::string& path) {
        if (!j.is_array()) fail(path, "expected an array");
        return j;
    }
    static float number(const Json& j, const std::string& path) {
        if (!j.is_number()) fail(path, "expected a number");
        const double d = j.get<double>();
        if (!std::isfinite(d) || std::fabs(d) > double(std::numeric_limits<float>::max()))
            fail(path, "not a finite float");
        return static_cast<float>(d);
    }
    static Vec3 vec3(const Json& j, const std::string& path) {
        if (!j.is_array() || j.size() != 3) fail(path, "expected an array of 3 numbers");
        return {number(j[0], at(path, 0)), number(j[1], at(path, 1)), number(j[2], at(path, 2))};
    }

    Mesh mesh(const Json& j, const std::string& path) const {
        if (!j.is_string()) fail(path, "expected a scene name or a mesh path");
        const std::string ref = j.get<std::string>();
        const std::filesystem::path local = base / ref;
        std::error_code ec;
        try {
            if (std::filesystem::path(ref).is_relative() && std::filesystem::is_regular_file(local, ec))
                return load_scene(local.string());
            return load_scene(ref);
        } catch (const Error& e) {
            fail(path, e.what());
        }
    }

    Geometry geometry(const Json& j, const std::string& path, std::map<std::string, std::uint32_t>& names,
                      std::uint32_t index) const {
        only_keys(j, path, {"name", "mesh", "spheres", "boxes"});
        if (j.contains("name")) {
            if (!j["name"].is_string()) fail(key(path, "name"), "expected a string");
            if (!names.emplace(j["name"].get<std::string>(), index).second) fail(key(path, "name"), "duplicate name");
        }
        const int kinds = int(j.contains("mesh")) + int(j.contains("spheres")) + int(j.contains("boxes"));
        if (kinds != 1) fail(path, "needs exactly one of mesh, spheres, boxes");
        if (j.contains("mesh")) return mesh(j["mesh"], key(path, "mesh"));
        if (j.contains("spheres")) {
            SphereSet s;
            const std::string p = key(path, "spheres");
            const Json& a = array(j["spheres"], p);
            for (std::size_t i = 0; i < a.size(); ++i) {
                const std::string q = at(p, i);
                only_keys(a[i], q, {"center", "radius"});
                if (!a[i].contains("center") || !a[i].contains("radius")) fail(q, "needs center and radius");
                const Sphere sp{vec3(a[i]["center"], key(q, "center")), number(a[i]["radius"], key(q, "radius"))};
                if (sp.radius < 0.0f) fail(key(q, "radius"), "negative");
                s.spheres.push_back(sp);
            }
            return s;
        }
        BoxSet b;
        const std::string p = key(path, "boxes");
        const Json& a = array(j["boxes"], p);
        for (std::size_t i = 0; i < a.size(); ++i) {
            const std::string q = at(p, i);
            only_keys(a[i], q, {"min", "max"});
            if (!a[i].contains("min") || !a[i].contains("max")) fail(q, "needs min and max");
            const Aabb box{vec3(a[i]["min"], key(q, "min")), vec3(a[i]["max"], key(q, "max"))};
            if (box.is_empty()) fail(q, "min > max");
            b.boxes.push_back(box);
        }
        return b;
    }

    static Affine3 transform(const Json& j, const std::string& path) {
        if (!j.is_array() || j.size() != 3) fail(path, "expected 3 rows of 4 numbers");
        Affine3 t;
        for (int r = 0; r < 3; ++r) {
            const std::string row = at(path, std::size_t(r));
            if (!j[r].is_array() || j[r].size() != 4) fail(row, "expected 4 numbers");
            for (int c = 0; c < 4; ++c) t.m[r][c] = number(j[r][c], at(row, std::size_t(c)));
        }
        return t;
    }

    static Instance instance(const Json& j, const std::string& path, const std::map<std::string, std::uint32_t>& names,
                             std::size_t geometries) {
        only_keys(j, path, {"geometry", "transform", "translate", "rotate", "scale"});
        Instance in;
        const std::string gp = key(path, "geometry");
        if (!j.contains("geometry")) fail(path, "needs geometry");
        const Json& g = j["geometry"];
        if (g.is_string()) {
            auto it = names.find(g.get<std::string>());
            if (it == names.end()) fail(gp, "no geometry named '" + g.get<std::string>() + "'");
            in.geometry = it->second;
        } else if (g.is_number_unsigned()) {
            const auto v = g.get<std::uint64_t>();
            if (v >= geometries) fail(gp, "no geometry " + std::to_string(v));
            in.geometry = std::uint32_t(v);
        } else {
            fail(gp, "expected a geometry index or name");
        }
        const bool parts = j.contains("translate") || j.contains("rotate") || j.contains("scale");
        if (j.contains("transform")) {
            if (parts) fail(path, "transform excludes translate, rotate, scale");
            in.transform = transform(j["transform"], key(path, "transform"));
        } else if (parts) {
            Affine3 t, r, s;  // x_world = T R S x
            if (j.contains("translate")) t = Affine3::translation(vec3(j["translate"], key(path, "translate")));
            if (j.contains("rotate")) {
                const std::string rp = key(path, "rotate");
                only_keys(j["rotate"], rp, {"axis", "degrees"});
                if (!j["rotate"].contains("axis") || !j["rotate"].contains("degrees")) fail(rp, "needs axis and degrees");
                const Vec3 axis = vec3(j["rotate"]["axis"], key(rp, "axis"));
                if (axis.x == 0.0f && axis.y == 0.0f && axis.z == 0.0f) fail(key(rp, "axis"), "zero");
                r = Affine3::rotation(axis, double(number(j["rotate"]["degrees"], key(rp, "degrees"))) *
                                                std::numbers::pi / 180.0);
            }
            if (j.contains("scale")) {
                const std::string sp = key(path, "scale");
                if (j["scale"].is_array()) {
                    const Vec3 v = vec3(j["scale"], sp);
                    s.m[0][0] = v.x;
                    s.m[1][1] = v.y;
                    s.m[2][2] = v.z;
                } else {
                    s = Affine3::scaling(number(j["scale"], sp));
                }
            }
            in.transform = t * r * s;
        }
        try {
            invert(in.transform);
        } catch (const Error& e) {
            const std::string what = e.what();
            fail(key(path, "transform"), what.substr(what.find(':') + 2));
        }
        return in;
    }

    SceneDesc scene(const Json& root) const {
        only_keys(root, "", {"geometries", "instances", "planes"});
        SceneDesc s;
        std::map<std::string, std::uint32_t> names;
        if (root.contains("geometries")) {
            const Json& a = array(root["geometries"], "geometries");
            for (std::size_t i = 0; i < a.size(); ++i)
                s.geometries.push_back(geometry(a[i], at("geometries", i), names, std::uint32_t(i)));
        }
        if (root.contains("instances")) {
            const Json& a = array(root["instances"], "instances");
            for (std::size_t i = 0; i < a.size(); ++i)
                s.instances.push_back(instance(a[i], at("instances", i), names, s.geometries.size()));
        }
        if (root.contains("planes")) {
            const Json& a = array(root["planes"], "planes");
            for (std::size_t i = 0; i < a.size(); ++i) {
                const std::string q = at("planes", i);
                only_keys(a[i], q, {"point", "normal"});
                if (!a[i].contains("point") || !a[i].contains("normal")) fail(q, "needs point and normal");
                const Plane p{vec3(a[i]["point"], key(q, "point")), vec3(a[i]["normal"], key(q, "normal"))};
                if (p.normal.x == 0.0f && p.normal.y == 0.0f && p.normal.z == 0.0f) fail(key(q, "normal"), "zero");
                s.planes.push_back(p);
            }
        }
        validate(s);  // whatever the checks above missed (e.g. a mesh the BVH rejects)
        return s;
    }
};

}  // namespace

SceneDesc parse_scene_json(std::string_view text, const std::filesystem::path& base_dir, std::string_view label) {
    Json root;
    // Strict: a key repeated within one object is an error (nlohmann-json would keep the last).
    std::vector<std::set<std::string>> keys;
    std::string duplicate;
    const Json::parser_callback_t reject_duplicates = [&](int, Json::parse_event_t ev, Json& parsed) {
        if (ev == Json::parse_event_t::object_start) keys.emplace_back();
        else if (ev == Json::parse_event_t::object_end && !keys.empty()) keys.pop_back();
        else if (ev == Json::parse_event_t::key && !keys.empty() && !keys.back().insert(parsed.get<std::string>()).second &&
                 duplicate.empty())
            duplicate = parsed.get<std::string>();
        return true;
    };
    try {
        root = Json::parse(text.begin(), text.end(), reject_duplicates);
    } catch (const Json::exception& e) {
        throw Error(std::string(label) + ": not valid JSON: " + e.what());
    }
    if (!duplicate.empty()) throw Error(std::string(label) + ": duplicate key '" + duplicate + "'");
    try {
        return Parser{base_dir}.scene(root);
    } catch (const Error& e) {
        throw Error(std::string(label) + ": " + e.what());
    }
}

// Read as the meshes are (read_file): a regular file only (symlinks resolved; a
// FIFO, device or folder refused at once), raw or gzip, within json_limit.
SceneDesc load_scene_json(const std::filesystem::path& file) {
    const std::string label = file.string();
    std::vector<char> text;
    try {
        text = detail::read_file(file, detail::json_limit);
    } catch (const std::bad_alloc&) {
        throw Error(label + ": out of memory while reading the file");
    }
    if (text.empty()) throw Error(label + ": file is empty (0 bytes)");
    return parse_scene_json(std::string_view(text.data(), text.size()), file.parent_path(), label);
}

}  // namespace simdbvh::scene
