// The JSON scene format (nlohmann-json), strict: every problem is reported
// with its JSON path, e.g. "scene.json: instances[3].transform: singular".
// Without "instances", every geometry is placed once with the identity;
// "instances": [] places none. Mesh references: json_mesh_path (Parser::mesh).
#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <map>
#include <new>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "simdbvh/kernels/error.h"
#include "simdbvh/io/load.h"
#include "simdbvh/workloads/scene_desc.h"
#include "simdbvh/workloads/scenes.h"
#include "simdbvh/io/internal/size_limit.h"

namespace simdbvh::workloads {

namespace {

using Json = nlohmann::json;

// Text from the file in messages goes through the loaders' helpers
// (text.h): quote() cuts it to 40 bytes, and both escape every byte outside
// printable ASCII, so a 1 MB key or an ESC in a name reaches no terminal.
std::string json_quote(std::string_view s) { return io::detail::quote(s); }
// A member in a JSON path: .key for a plain key (letters, digits, '_', at
// most 40), ['...'] (quoted) for any other.
std::string json_key(const std::string& path, std::string_view k) {
    const bool plain = !k.empty() && k.size() <= 40 && std::all_of(k.begin(), k.end(), [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
    });
    if (!plain) return path + "[" + json_quote(k) + "]";
    return path.empty() ? std::string(k) : path + "." + std::string(k);
}

// The document, built by our own SAX handler over the text in place (no copy).
// Not nlohmann's parser callback: its DOM builder, after every object or
// array it closes, walks the whole enclosing container looking for discarded
// values, so an array of n objects took n^2 / 2 steps (10^6 instances: 270 s).
// Here each event does constant work (a key: one map insertion, which also
// finds a repeated key), and nesting deeper than kMaxDepth stops the parse.
constexpr std::size_t kMaxDepth = 512;  // the format itself nests 6 deep (a sphere's center)

class DocumentBuilder {
public:
    Json root;
    std::string error;                    // set when a handler stops the parse
    std::optional<std::size_t> error_at;  // nlohmann's syntax errors: characters read when it stopped

    bool null() { return put(nullptr); }
    bool boolean(bool v) { return put(v); }
    bool number_integer(Json::number_integer_t v) { return put(v); }
    bool number_unsigned(Json::number_unsigned_t v) { return put(v); }
    bool number_float(Json::number_float_t v, const std::string&) { return put(v); }
    bool string(std::string& v) { return put(std::move(v)); }
    bool binary(Json::binary_t&) { return stop("not valid JSON: a binary value"); }
    bool start_object(std::size_t) { return open(Json::object()); }
    bool start_array(std::size_t) { return open(Json::array()); }
    bool end_object() { return close(); }
    bool end_array() { return close(); }
    bool key(std::string& k) {
        auto& members = stack_.back().value->get_ref<Json::object_t&>();
        const auto [it, inserted] = members.emplace(std::move(k), nullptr);
        if (!inserted) return stop(where() + "duplicate key " + json_quote(it->first));
        slot_ = &it->second;
        slot_key_ = &it->first;
        return true;
    }
    bool parse_error(std::size_t position, const std::string&, const nlohmann::detail::exception& e) {
        error_at = position;
        return stop(e.what());
    }

private:
    struct Level {
        Json* value;
        const std::string* key;  // its key in the enclosing object (nullptr: an array element or the root)
    };
    std::vector<Level> stack_;
    Json* slot_ = nullptr;  // where an object's next value goes (set by key())
    const std::string* slot_key_ = nullptr;

    bool stop(std::string what) {
        error = std::move(what);
        return false;
    }
    // Stores a value where the parse is: the root, the end of an array or an object's last key.
    Json* place(Json&& v, const std::string** key) {
        *key = nullptr;
        if (stack_.empty()) {
            root = std::move(v);
            return &root;
        }
        Json& top = *stack_.back().value;
        if (top.is_array()) {
            top.get_ref<Json::array_t&>().push_back(std::move(v));
            return &top.get_ref<Json::array_t&>().back();
        }
        *slot_ = std::move(v);
        *key = slot_key_;
        return slot_;
    }
    template <class V>
    bool put(V&& v) {
        const std::string* key;
        place(Json(std::forward<V>(v)), &key);
        return true;
    }
    bool open(Json&& container) {
        if (stack_.size() >= kMaxDepth)
            return stop("not valid JSON for a scene: arrays and objects nested deeper than " +
                        std::to_string(kMaxDepth) + " levels (a scene nests at most 6)");
        const std::string* key;
        Json* v = place(std::move(container), &key);
        stack_.push_back({v, key});
        return true;
    }
    bool close() {
        stack_.pop_back();
        return true;
    }
    // The JSON path of the innermost open container, as "path: " ("" at the root).
    std::string where() const {
        std::string path;
        for (std::size_t i = 1; i < stack_.size(); ++i) {
            const Json& parent = *stack_[i - 1].value;
            if (parent.is_array()) path += "[" + std::to_string(parent.size() - 1) + "]";
            else path = json_key(path, *stack_[i].key);
        }
        return path.empty() ? std::string() : path + ": ";
    }
};

// nlohmann's lexer copies each character it reads into a token buffer that
// it clears only where a string or a number starts, so a long run of
// whitespace was held a second time there (300 MB of spaces: 1.1 GB). The
// parser reads the text through this iterator, which passes at most
// kMaxBlank characters of a run of whitespace outside strings (whitespace
// only separates tokens, so the document is the same) and notes each skip,
// so that error positions are the file's own lines and columns.
constexpr std::size_t kMaxBlank = 4096;

struct Skips {
    // (characters passed when the skip happened, characters skipped so far), in order.
    std::vector<std::pair<std::size_t, std::size_t>> at;
    // The text offset of the `passed`-th character passed.
    std::size_t offset(std::size_t passed) const {
        auto it = std::upper_bound(at.begin(), at.end(), std::pair(passed, std::size_t(0)),
                                   [](const auto& a, const auto& b) { return a.first < b.first; });
        return passed + (it == at.begin() ? 0 : std::prev(it)->second);
    }
};

class BlankSqueezer {
public:
    using iterator_category = std::forward_iterator_tag;
    using value_type = char;
    using difference_type = std::ptrdiff_t;
    using pointer = const char*;
    using reference = const char&;

    BlankSqueezer() = default;
    BlankSqueezer(const char* p, const char* end, Skips* skips) : p_(p), end_(end), skips_(skips) {}
    reference operator*() const { return *p_; }
    bool operator==(const BlankSqueezer& o) const { return p_ == o.p_; }
    bool operator!=(const BlankSqueezer& o) const { return p_ != o.p_; }
    BlankSqueezer operator++(int) {
        BlankSqueezer before = *this;
        ++*this;
        return before;
    }
    BlankSqueezer& operator++() {
        const char c = *p_++;
        ++passed_;
        if (in_string_) {
            if (escape_) escape_ = false;
            else if (c == '\\') escape_ = true;
            else if (c == '"') in_string_ = false;
            return *this;
        }
        if (!blank(c)) {
            in_string_ = c == '"';
            run_ = 0;
            return *this;
        }
        if (++run_ < kMaxBlank) return *this;
        const char* q = p_;
        while (q != end_ && blank(*q)) ++q;
        if (q != p_) {
            skipped_ += std::size_t(q - p_);
            skips_->at.emplace_back(passed_, skipped_);
            p_ = q;
        }
        run_ = 0;
        return *this;
    }

private:
    static bool blank(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }
    const char* p_ = nullptr;
    const char* end_ = nullptr;
    Skips* skips_ = nullptr;
    std::size_t passed_ = 0, skipped_ = 0, run_ = 0;
    bool in_string_ = false, escape_ = false;
};

// "at line L, column C" of the character at `offset` (counted from 1 as nlohmann counts them).
std::string text_position(std::string_view text, std::size_t offset) {
    offset = std::min(offset, text.size());
    const std::string_view before = text.substr(0, offset);
    const std::size_t lines = std::size_t(std::count(before.begin(), before.end(), '\n'));
    const std::size_t nl = before.rfind('\n');
    const std::size_t column = nl == std::string_view::npos ? offset : offset - nl - 1;
    return "at line " + std::to_string(lines + 1) + ", column " + std::to_string(column);
}

Json parse_document(std::string_view text) {
    DocumentBuilder b;
    Skips skips;
    const BlankSqueezer first(text.data(), text.data() + text.size(), &skips),
        last(text.data() + text.size(), nullptr, nullptr);
    if (Json::sax_parse(first, last, &b, Json::input_format_t::json, /*strict=*/true)) return std::move(b.root);
    if (b.error_at) {
        // nlohmann's message after its own position ("... column N: ").
        std::string what = b.error;
        const std::size_t col = what.find(", column ");
        const std::size_t colon = col == std::string::npos ? col : what.find(": ", col);
        if (colon != std::string::npos) what = what.substr(colon + 2);
        throw Error("not valid JSON " + text_position(text, skips.offset(*b.error_at)) + ": " +
                    io::detail::printable(what, 200));
    }
    throw Error(b.error.empty() ? std::string("not valid JSON") : b.error);
}

// A JSON path, spelled out only when a message needs it: each level points to
// its parent (a temporary or a local of the caller, which outlives it).
struct Path {
    static constexpr std::size_t kNoIndex = std::size_t(-1);
    const Path* parent = nullptr;
    std::string_view name;         // a member's key, or
    std::size_t index = kNoIndex;  // an array element's index

    Path operator[](std::size_t i) const { return {this, {}, i}; }
    Path operator/(std::string_view k) const { return {this, k, kNoIndex}; }
    std::string str() const {
        if (!parent) return std::string();
        std::string s = parent->str();
        if (index != kNoIndex) return s + "[" + std::to_string(index) + "]";
        return json_key(s, name);
    }
};

struct Parser {
    std::filesystem::path base;

    [[noreturn]] static void fail(const Path& path, const std::string& what) {
        const std::string p = path.str();
        throw Error((p.empty() ? std::string("(root)") : p) + ": " + what);
    }

    static void only_keys(const Json& j, const Path& path, std::initializer_list<std::string_view> allowed) {
        if (!j.is_object()) fail(path, "expected an object");
        for (auto it = j.begin(); it != j.end(); ++it) {
            bool ok = false;
            for (std::string_view a : allowed) ok = ok || it.key() == a;
            if (!ok) fail(path / it.key(), "unknown key");
        }
    }
    // The member `k` of an object already checked by only_keys, or nullptr.
    static const Json* member(const Json& j, std::string_view k) {
        const auto it = j.find(k);
        return it == j.end() ? nullptr : &*it;
    }
    static const Json& array(const Json& j, const Path& path) {
        if (!j.is_array()) fail(path, "expected an array");
        return j;
    }
    static float number(const Json& j, const Path& path) {
        if (!j.is_number()) fail(path, "expected a number");
        const double d = j.get<double>();
        if (!std::isfinite(d) || std::fabs(d) > double(std::numeric_limits<float>::max()))
            fail(path, "not a finite float");
        return static_cast<float>(d);
    }
    static Vec3 vec3(const Json& j, const Path& path) {
        if (!j.is_array() || j.size() != 3) fail(path, "expected an array of 3 numbers");
        return {number(j[0], path[0]), number(j[1], path[1]), number(j[2], path[2])};
    }

    // A mesh reference, read as json_mesh_path says: a string with a '/' or a
    // '.' is a file path relative to the JSON file's folder (unless absolute),
    // never looked up in the current folder; anything else is a mesh name, and
    // one that load_scene does not know is an error here, not a file.
    Mesh mesh(const Json& j, const Path& path) const {
        if (!j.is_string()) fail(path, "expected a mesh name or a mesh file path");
        const std::string& ref = j.get_ref<const std::string&>();
        // A file name cannot hold a NUL ("\u0000"): opened as a C string, the path would end there.
        if (ref.find('\0') != std::string::npos)
            fail(path, json_quote(ref) + " contains a NUL character (\\u0000), which no file name or mesh name has");
        const std::optional<std::filesystem::path> file = json_mesh_path(base, ref);
        if (!file && !is_mesh_name(ref)) {
            std::string names;
            for (const std::string& n : scene_names()) names += (names.empty() ? "" : ", ") + n;
            fail(path, json_quote(ref) + " is neither a mesh name (" + names +
                           ") nor a file path (a mesh file's name has its extension: .ply, .obj, .stl or .off, "
                           "optionally .gz)");
        }
        try {
            return file ? io::load_mesh(*file) : load_scene(ref);
        } catch (const Error& e) {
            fail(path, e.what());
        }
    }

    Geometry geometry(const Json& j, const Path& path, std::map<std::string, std::uint32_t>& names,
                      std::uint32_t index) const {
        only_keys(j, path, {"name", "mesh", "spheres", "boxes"});
        if (const Json* n = member(j, "name")) {
            if (!n->is_string()) fail(path / "name", "expected a string");
            if (!names.emplace(n->get<std::string>(), index).second)
                fail(path / "name", "duplicate name " + json_quote(n->get_ref<const std::string&>()));
        }
        const Json* m = member(j, "mesh");
        const Json* sph = member(j, "spheres");
        const Json* box = member(j, "boxes");
        if (int(m != nullptr) + int(sph != nullptr) + int(box != nullptr) != 1)
            fail(path, "needs exactly one of mesh, spheres, boxes");
        if (m) return mesh(*m, path / "mesh");
        if (sph) {
            SphereSet s;
            const Path p = path / "spheres";
            const Json& a = array(*sph, p);
            s.spheres.reserve(a.size());
            for (std::size_t i = 0; i < a.size(); ++i) {
                const Path q = p[i];
                only_keys(a[i], q, {"center", "radius"});
                const Json* c = member(a[i], "center");
                const Json* r = member(a[i], "radius");
                if (!c || !r) fail(q, "needs center and radius");
                const Sphere sp{vec3(*c, q / "center"), number(*r, q / "radius")};
                if (sp.radius < 0.0f) fail(q / "radius", "negative");
                s.spheres.push_back(sp);
            }
            return s;
        }
        BoxSet b;
        const Path p = path / "boxes";
        const Json& a = array(*box, p);
        b.boxes.reserve(a.size());
        for (std::size_t i = 0; i < a.size(); ++i) {
            const Path q = p[i];
            only_keys(a[i], q, {"min", "max"});
            const Json* lo = member(a[i], "min");
            const Json* hi = member(a[i], "max");
            if (!lo || !hi) fail(q, "needs min and max");
            const Aabb bx{vec3(*lo, q / "min"), vec3(*hi, q / "max")};
            if (bx.is_empty()) fail(q, "min > max");
            b.boxes.push_back(bx);
        }
        return b;
    }

    static Affine3 transform(const Json& j, const Path& path) {
        if (!j.is_array() || j.size() != 3) fail(path, "expected 3 rows of 4 numbers");
        Affine3 t;
        for (std::size_t r = 0; r < 3; ++r) {
            const Path row = path[r];
            if (!j[r].is_array() || j[r].size() != 4) fail(row, "expected 4 numbers");
            for (std::size_t c = 0; c < 4; ++c) t.m[r][c] = number(j[r][c], row[c]);
        }
        return t;
    }

    static Instance instance(const Json& j, const Path& path, const std::map<std::string, std::uint32_t>& names,
                             std::size_t geometries) {
        only_keys(j, path, {"geometry", "transform", "translate", "rotate", "scale"});
        Instance in;
        const Json* g = member(j, "geometry");
        if (!g) fail(path, "needs geometry");
        if (g->is_string()) {
            auto it = names.find(g->get_ref<const std::string&>());
            if (it == names.end())
                fail(path / "geometry", "no geometry named " + json_quote(g->get_ref<const std::string&>()));
            in.geometry = it->second;
        } else if (g->is_number_unsigned()) {
            const auto v = g->get<std::uint64_t>();
            if (v >= geometries) fail(path / "geometry", "no geometry " + std::to_string(v));
            in.geometry = std::uint32_t(v);
        } else {
            fail(path / "geometry", "expected a geometry index or name");
        }
        const Json* tr = member(j, "translate");
        const Json* rot = member(j, "rotate");
        const Json* sc = member(j, "scale");
        if (const Json* m = member(j, "transform")) {
            if (tr || rot || sc) fail(path, "transform excludes translate, rotate, scale");
            in.transform = transform(*m, path / "transform");
        } else if (tr || rot || sc) {
            Affine3 t, r, s;  // x_world = T R S x
            if (tr) t = Affine3::translation(vec3(*tr, path / "translate"));
            if (rot) {
                const Path rp = path / "rotate";
                only_keys(*rot, rp, {"axis", "degrees"});
                const Json* axis_j = member(*rot, "axis");
                const Json* deg_j = member(*rot, "degrees");
                if (!axis_j || !deg_j) fail(rp, "needs axis and degrees");
                const Vec3 axis = vec3(*axis_j, rp / "axis");
                if (axis.x == 0.0f && axis.y == 0.0f && axis.z == 0.0f) fail(rp / "axis", "zero");
                r = Affine3::rotation(axis, double(number(*deg_j, rp / "degrees")) * std::numbers::pi / 180.0);
            }
            if (sc) {
                const Path sp = path / "scale";
                if (sc->is_array()) {
                    const Vec3 v = vec3(*sc, sp);
                    s.m[0][0] = v.x;
                    s.m[1][1] = v.y;
                    s.m[2][2] = v.z;
                } else {
                    s = Affine3::scaling(number(*sc, sp));
                }
            }
            in.transform = t * r * s;
        }
        try {
            invert(in.transform);
        } catch (const Error& e) {
            const std::string what = e.what();
            fail(path / "transform", what.substr(what.find(':') + 2));
        }
        return in;
    }

    SceneDesc scene(const Json& root) const {
        const Path top;
        only_keys(root, top, {"geometries", "instances", "planes"});
        SceneDesc s;
        std::map<std::string, std::uint32_t> names;
        if (const Json* g = member(root, "geometries")) {
            const Path p = top / "geometries";
            const Json& a = array(*g, p);
            s.geometries.reserve(a.size());
            for (std::size_t i = 0; i < a.size(); ++i)
                s.geometries.push_back(geometry(a[i], p[i], names, std::uint32_t(i)));
        }
        // Without "instances" every geometry is placed once, untransformed (as
        // simdbvh.Scene without instances= in Python); an explicit list, even
        // an empty one, places exactly what it lists.
        if (const Json* in = member(root, "instances")) {
            const Path p = top / "instances";
            const Json& a = array(*in, p);
            s.instances.reserve(a.size());
            for (std::size_t i = 0; i < a.size(); ++i)
                s.instances.push_back(instance(a[i], p[i], names, s.geometries.size()));
        } else {
            for (std::size_t g = 0; g < s.geometries.size(); ++g) s.instances.push_back({std::uint32_t(g), Affine3{}});
        }
        if (const Json* pl = member(root, "planes")) {
            const Path p = top / "planes";
            const Json& a = array(*pl, p);
            s.planes.reserve(a.size());
            for (std::size_t i = 0; i < a.size(); ++i) {
                const Path q = p[i];
                only_keys(a[i], q, {"point", "normal"});
                const Json* pt = member(a[i], "point");
                const Json* nm = member(a[i], "normal");
                if (!pt || !nm) fail(q, "needs point and normal");
                const Plane pln{vec3(*pt, q / "point"), vec3(*nm, q / "normal")};
                if (pln.normal.x == 0.0f && pln.normal.y == 0.0f && pln.normal.z == 0.0f) fail(q / "normal", "zero");
                s.planes.push_back(pln);
            }
        }
        validate(s);  // whatever the checks above missed (e.g. a mesh the BVH rejects)
        return s;
    }
};

}  // namespace

SceneDesc parse_scene_json(std::string_view text, const std::filesystem::path& base_dir, std::string_view label) {
    const std::string file = io::detail::printable(label);
    Json root;
    try {
        root = parse_document(text);
    } catch (const Error& e) {
        throw Error(file + ": " + e.what());
    } catch (const std::bad_alloc&) {
        throw Error(file + ": out of memory while parsing the JSON");
    }
    try {
        return Parser{base_dir}.scene(root);
    } catch (const Error& e) {
        throw Error(file + ": " + e.what());
    }
}

std::optional<std::filesystem::path> json_mesh_path(const std::filesystem::path& json_dir, std::string_view ref) {
    if (ref.find_first_of("/.") == std::string_view::npos) return std::nullopt;
    const std::filesystem::path p{std::string(ref)};
    return p.is_absolute() ? p : json_dir / p;
}

// Read as the meshes are (read_file): a regular file only (symlinks resolved; a
// FIFO, device or folder refused at once), raw or gzip, within json_limit.
SceneDesc load_scene_json(const std::filesystem::path& file) {
    const std::string label = file.string();
    std::vector<char> text;
    try {
        text = io::detail::read_file(file, io::detail::json_limit);
    } catch (const std::bad_alloc&) {
        throw Error(io::detail::printable(label) + ": out of memory while reading the file");
    }
    if (text.empty()) throw Error(io::detail::printable(label) + ": file is empty (0 bytes)");
    return parse_scene_json(std::string_view(text.data(), text.size()), file.parent_path(), label);
}

}  // namespace simdbvh::workloads
