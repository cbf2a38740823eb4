#include "support/scene.h"

#include <zlib.h>

#include <atomic>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <unistd.h>

#include "simdbvh/workloads/scenes.h"

namespace test {

bool available(std::string_view name) {
    for (const std::string& n : simdbvh::workloads::scene_names())
        if (n == name && !simdbvh::workloads::is_cached(name))
            return name == "icosphere" || name == "soup" || name == "terrain";
    return true;
}

std::string skip_message(std::string_view name) {
    return "scene '" + std::string(name) + "' is not cached in " + simdbvh::workloads::cache_dir().string() +
           "; run scripts/fetch_scenes.sh (needs npm) to enable this test";
}

namespace {
void record_skip(std::string_view name) { GTEST_SKIP() << skip_message(name); }
}  // namespace

simdbvh::Mesh load_or_skip(std::string_view name) {
    if (!available(name)) {
        record_skip(name);
        return {};
    }
    return simdbvh::workloads::load_scene(name);
}

simdbvh::Mesh one_triangle() {
    simdbvh::Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.triangles = {{0, 1, 2}};
    return m;
}

simdbvh::Mesh unit_cube() {
    simdbvh::Mesh m;
    for (int i = 0; i < 8; ++i) m.positions.push_back({float(i & 1), float((i >> 1) & 1), float((i >> 2) & 1)});
    const std::uint32_t q[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    for (const auto& f : q) {
        m.triangles.push_back({f[0], f[1], f[2]});
        m.triangles.push_back({f[0], f[2], f[3]});
    }
    return m;
}

TempDir::TempDir() : TempDir(false) {}

TempDir::TempDir(bool in_memory) {
    static std::atomic<unsigned> counter{0};
    std::error_code ec;
    auto base = std::filesystem::temp_directory_path();
    if (in_memory && std::filesystem::is_directory("/dev/shm", ec) && ::access("/dev/shm", W_OK) == 0)
        base = "/dev/shm";
    for (int attempt = 0; attempt < 1000; ++attempt) {
        auto p = base / ("simdbvh_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
        if (std::filesystem::create_directory(p)) {
            path_ = p;
            return;
        }
    }
    throw std::runtime_error("cannot create a temporary folder");
}

TempDir::~TempDir() {
    std::error_code ec;
    // Make read-only subfolders writable again so they can be removed.
    for (auto it = std::filesystem::recursive_directory_iterator(path_, ec);
         !ec && it != std::filesystem::recursive_directory_iterator(); it.increment(ec))
        if (it->is_directory(ec)) std::filesystem::permissions(it->path(), std::filesystem::perms::owner_all, ec);
    std::filesystem::remove_all(path_, ec);
}

void write_text(const std::filesystem::path& file, std::string_view text) {
    std::ofstream out(file, std::ios::binary);
    out.write(text.data(), std::streamsize(text.size()));
    if (!out) throw std::runtime_error("cannot write " + file.string());
}

std::string read_bytes(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw std::runtime_error("cannot read " + file.string());
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

void write_gzip(const std::filesystem::path& file, std::string_view bytes) {
    gzFile gz = gzopen(file.c_str(), "wb");
    if (!gz) throw std::runtime_error("cannot write " + file.string());
    if (!bytes.empty() && gzwrite(gz, bytes.data(), unsigned(bytes.size())) != int(bytes.size())) {
        gzclose(gz);
        throw std::runtime_error("gzwrite failed for " + file.string());
    }
    if (gzclose(gz) != Z_OK) throw std::runtime_error("gzclose failed for " + file.string());
}

std::filesystem::path data_file(std::string_view name) {
    return std::filesystem::path(SIMDBVH_SOURCE_DIR) / "tests" / "data" / std::string(name);
}

}  // namespace test
