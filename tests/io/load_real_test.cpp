// Real-world files: the npm scenes (skipped when not fetched) and Debian's
// assimp-testmodels (skipped when not installed), including its invalid/
// folder, every file of which must throw simdbvh::Error.
#include <gtest/gtest.h>
#include <zlib.h>

#include <bit>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include "simdbvh/kernels/error.h"
#include "simdbvh/io/load.h"
#include "simdbvh/workloads/scenes.h"
#include "support/scene.h"

namespace fs = std::filesystem;
using simdbvh::Mesh;
using simdbvh::io::load_mesh;

namespace {

std::string gunzip(const fs::path& file) {
    gzFile gz = gzopen(file.c_str(), "rb");
    if (!gz) throw std::runtime_error("cannot open " + file.string());
    std::string out;
    char buf[1 << 16];
    int n;
    while ((n = gzread(gz, buf, sizeof buf)) > 0) out.append(buf, std::size_t(n));
    gzclose(gz);
    return out;
}

fs::path assimp_models() {
    for (const char* d :
         {"/usr/share/assimp/models", "/usr/share/assimp-testmodels/models", "/usr/share/assimp-testmodels"})
        if (fs::is_directory(d)) return d;
    return {};
}

}  // namespace

// Every dragon vertex equals strtof of its text, bit for bit (parsed here independently).
TEST(RealScenes, DragonVerticesEqualStrtof) {
    if (!simdbvh::workloads::is_cached("dragon")) GTEST_SKIP() << test::skip_message("dragon");
    const fs::path file = *simdbvh::workloads::cached_scene_file("dragon");
    const std::string text = gunzip(file);
    const std::size_t body = text.find("end_header\n");
    ASSERT_NE(body, std::string::npos);
    const std::size_t ev = text.find("element vertex ");
    const std::size_t ef = text.find("element face ");
    ASSERT_LT(ev, body);
    ASSERT_LT(ef, body);
    const std::size_t nv = std::strtoull(text.c_str() + ev + 15, nullptr, 10);
    const std::size_t nf = std::strtoull(text.c_str() + ef + 13, nullptr, 10);
    EXPECT_EQ(nv, 437645u);
    EXPECT_EQ(nf, 871414u);

    const Mesh m = load_mesh(file);
    ASSERT_EQ(m.positions.size(), nv);
    ASSERT_EQ(m.triangles.size(), nf);  // all faces are triangles
    const char* p = text.c_str() + body + 11;
    std::size_t mismatches = 0;
    for (std::size_t i = 0; i < nv; ++i) {
        for (int k = 0; k < 3; ++k) {
            char* end = nullptr;
            const float want = std::strtof(p, &end);
            ASSERT_NE(end, p) << "vertex " << i;
            p = end;
            if (std::bit_cast<std::uint32_t>(want) != std::bit_cast<std::uint32_t>(m.positions[i][k]) &&
                mismatches++ < 5)
                ADD_FAILURE() << "vertex " << i << " coord " << k << ": " << m.positions[i][k] << " != strtof " << want;
        }
    }
    EXPECT_EQ(mismatches, 0u);
    // Faces in file order, no reordering or merging.
    std::size_t face_mismatches = 0;
    for (std::size_t f = 0; f < nf; ++f) {
        char* end = nullptr;
        ASSERT_EQ(std::strtol(p, &end, 10), 3) << "face " << f;
        p = end;
        for (int k = 0; k < 3; ++k) {
            const unsigned long idx = std::strtoul(p, &end, 10);
            p = end;
            if (m.triangles[f][k] != idx) ++face_mismatches;
        }
    }
    EXPECT_EQ(face_mismatches, 0u);
}

TEST(RealScenes, NamedScenesLoad) {
    struct Want {
        const char* name;
        std::size_t tris;
    };
    for (const Want w : {Want{"dragon-res2", 0}, Want{"dragon-res3", 0}, Want{"dragon-res4", 0}, Want{"bunny", 3674},
                         Want{"teapot", 992}}) {
        if (!simdbvh::workloads::is_cached(w.name)) {
            GTEST_SKIP() << test::skip_message(w.name);
        }
        const Mesh m = simdbvh::workloads::load_scene(w.name);
        EXPECT_GT(m.triangles.size(), 0u) << w.name;
        if (w.tris) {
            EXPECT_EQ(m.triangles.size(), w.tris) << w.name;
        }
        EXPECT_NO_THROW(simdbvh::validate(m)) << w.name;
    }
}

TEST(RealScenes, UncachedNamedSceneSaysHowToFetch) {
    test::TempDir dir;
    ::setenv("SIMDBVH_CACHE", dir.path().c_str(), 1);
    EXPECT_EQ(simdbvh::workloads::cache_dir(), dir.path());
    EXPECT_FALSE(simdbvh::workloads::is_cached("dragon"));
    try {
        simdbvh::workloads::load_scene("dragon");
        ADD_FAILURE() << "loaded an uncached scene";
    } catch (const simdbvh::Error& e) {
        EXPECT_NE(std::string(e.what()).find("scripts/fetch_scenes.sh"), std::string::npos) << e.what();
    }
}

// Without SIMDBVH_CACHE: the XDG rule (an absolute XDG_CACHE_HOME, else HOME's .cache), never a compiled-in path.
TEST(RealScenes, CacheFollowsTheXdgRule) {
    struct Env {
        const char* name;
        std::optional<std::string> old;
        explicit Env(const char* n) : name(n) {
            if (const char* v = std::getenv(n)) old = v;
        }
        ~Env() { old ? ::setenv(name, old->c_str(), 1) : ::unsetenv(name); }
    } cache("SIMDBVH_CACHE"), xdg("XDG_CACHE_HOME"), home("HOME");
    ::unsetenv("SIMDBVH_CACHE");
    ::setenv("HOME", "/home/someone", 1);
    ::setenv("XDG_CACHE_HOME", "/var/cache/me", 1);
    EXPECT_EQ(simdbvh::workloads::cache_dir(), fs::path("/var/cache/me/simdbvh/scenes"));
    ::setenv("XDG_CACHE_HOME", "relative/not/used", 1);
    EXPECT_EQ(simdbvh::workloads::cache_dir(), fs::path("/home/someone/.cache/simdbvh/scenes"));
    ::unsetenv("XDG_CACHE_HOME");
    EXPECT_EQ(simdbvh::workloads::cache_dir(), fs::path("/home/someone/.cache/simdbvh/scenes"));
    ::unsetenv("HOME");
    EXPECT_THROW(simdbvh::workloads::cache_dir(), simdbvh::Error);
}

TEST(AssimpModels, LoadValidModels) {
    const fs::path dir = assimp_models();
    if (dir.empty()) GTEST_SKIP() << "assimp-testmodels not installed (apt-get install assimp-testmodels)";
    struct Want {
        const char* file;
        std::size_t tris;
    };
    const Want wants[] = {
        {"PLY/cube.ply", 12},         // "uint8 int32 vertex_index", trailing spaces
        {"PLY/cube_binary.ply", 12},  // binary little endian
        {"PLY/cube_uv.ply", 12},      // Blender 2.77
        {"PLY/Wuson.ply", 0},         // Blender 2.47: non-standard "Created by Blender3D" header line
        {"PLY/float-color.ply", 1},
        {"PLY/points.ply", 0},  // vertices only
        {"OBJ/box.obj", 12},
        {"OBJ/box_without_lineending.obj", 12},
        {"OBJ/concave_polygon.obj", 0},
        {"OBJ/spider.obj", 0},
        {"OBJ/WusonOBJ.obj", 0},
        {"OBJ/cube_with_vertexcolors.obj", 12},
        {"OFF/Cube.off", 12},
        {"OFF/Wuson.off", 0},
        {"STL/triangle.stl", 1},
        {"STL/triangle_with_two_solids.stl", 2},
        {"STL/triangle_with_empty_solid.stl", 1},
        {"STL/Spider_ascii.stl", 0},
        {"STL/Spider_binary.stl", 0},
        {"STL/Wuson.stl", 0},
        {"STL/3DSMaxExport.STL", 0},
        {"STL/sphereWithHole.stl", 0},
    };
    for (const Want& w : wants) {
        SCOPED_TRACE(w.file);
        Mesh m;
        ASSERT_NO_THROW(m = load_mesh(dir / w.file));
        if (w.tris) {
            EXPECT_EQ(m.triangles.size(), w.tris);
        }
        EXPECT_NO_THROW(simdbvh::validate(m));
    }
    // The same models in different formats agree.
    EXPECT_EQ(load_mesh(dir / "STL/Spider_ascii.stl").triangles.size(),
              load_mesh(dir / "STL/Spider_binary.stl").triangles.size());
    EXPECT_EQ(load_mesh(dir / "PLY/Wuson.ply").triangles.size(), load_mesh(dir / "OFF/Wuson.off").triangles.size());
}

TEST(AssimpModels, InvalidFolderThrowsError) {
    const fs::path dir = assimp_models();
    if (dir.empty()) GTEST_SKIP() << "assimp-testmodels not installed (apt-get install assimp-testmodels)";
    std::size_t n = 0;
    for (const auto& e : fs::directory_iterator(dir / "invalid")) {
        if (!e.is_regular_file() || e.path().filename() == "readme.txt") continue;
        ++n;
        EXPECT_THROW(load_mesh(e.path()), simdbvh::Error) << e.path();
    }
    EXPECT_GE(n, 5u);
    // Other broken files in the collection.
    EXPECT_THROW(load_mesh(dir / "OFF/invalid.off"), simdbvh::Error);
    // A binary point cloud 69 bytes short of its 70051 declared 31-byte vertices (assimp tolerates it).
    EXPECT_THROW(load_mesh(dir / "PLY/pond.0.ply"), simdbvh::Error);
    // Its header lost the "element face" line: the index list is declared in the vertex element,
    // but the vertex lines lack it.
    EXPECT_THROW(load_mesh(dir / "PLY/issue623.ply"), simdbvh::Error);
    EXPECT_THROW(load_mesh(dir / "OBJ/number_formats.obj"), simdbvh::Error);  // "3.1+e2"
    EXPECT_THROW(load_mesh(dir / "OBJ/box_UTF16BE.obj"), simdbvh::Error);
}
