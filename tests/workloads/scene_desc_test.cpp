// Built-in scene descriptions and the strict JSON scene format: every error
// names the file and the JSON path.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "simdbvh/kernels/error.h"
#include "simdbvh/workloads/scene_desc.h"
#include "simdbvh/workloads/scenes.h"

namespace simdbvh::workloads {
namespace {

SceneDesc parse(const std::string& text) { return parse_scene_json(text, ".", "t.json"); }

void expect_error(const std::string& text, const std::string& want) {
    try {
        parse(text);
        ADD_FAILURE() << "no error for " << text << ", wanted " << want;
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("t.json: " + want), std::string::npos) << e.what();
    }
}

const std::string kSpheres = R"({"name": "balls", "spheres": [{"center": [0, 0, 0], "radius": 1}]})";

TEST(SceneJson, ParsesEveryKind) {
    const SceneDesc s = parse(R"({
      "geometries": [)" + kSpheres +
                              R"(,
        {"boxes": [{"min": [0, 0, 0], "max": [1, 2, 3]}]},
        {"mesh": "icosphere-1"}],
      "instances": [
        {"geometry": "balls"},
        {"geometry": 1, "transform": [[2, 0, 0, 1], [0, 2, 0, 2], [0, 0, 2, 3]]},
        {"geometry": 2, "translate": [5, 0, 0], "rotate": {"axis": [0, 0, 1], "degrees": 90}, "scale": 3}],
      "planes": [{"point": [0, -1, 0], "normal": [0, 1, 0]}]})");
    ASSERT_EQ(s.geometries.size(), 3u);
    EXPECT_EQ(std::get<SphereSet>(s.geometries[0]).spheres[0].radius, 1.0f);
    EXPECT_EQ(std::get<BoxSet>(s.geometries[1]).boxes[0].hi.z, 3.0f);
    EXPECT_EQ(std::get<Mesh>(s.geometries[2]).triangles.size(), 80u);
    ASSERT_EQ(s.instances.size(), 3u);
    EXPECT_EQ(s.instances[0].geometry, 0u);
    EXPECT_EQ(s.instances[1].transform.m[1][3], 2.0f);
    // T R S: (1, 0, 0) -> scale 3 -> rotate 90 about z -> (0, 3, 0) -> + (5, 0, 0).
    const Vec3 p = transform_point(s.instances[2].transform, {1, 0, 0});
    EXPECT_NEAR(p.x, 5.0f, 1e-6f);
    EXPECT_NEAR(p.y, 3.0f, 1e-6f);
    EXPECT_EQ(s.planes.size(), 1u);
}

TEST(SceneJson, ErrorsNameTheJsonPath) {
    const std::string g = R"("geometries": [)" + kSpheres + "]";
    expect_error("{" + g + R"(, "lights": []})", "lights: unknown key");
    expect_error(R"({"geometries": [{"spheres": [{"center": [0, 0, 0], "radius": -1}]}]})",
                 "geometries[0].spheres[0].radius: negative");
    expect_error(R"({"geometries": [{"spheres": [{"center": [0, "a", 0], "radius": 1}]}]})",
                 "geometries[0].spheres[0].center[1]: expected a number");
    expect_error(R"({"geometries": [{"spheres": [{"center": [0, 0, 0], "radius": 1, "color": 3}]}]})",
                 "geometries[0].spheres[0].color: unknown key");
    expect_error("{" + g + R"(, "instances": [{"geometry": 0}, {"geometry": 0}, {"geometry": 0}, {"geometry": 4}]})",
                 "instances[3].geometry: no geometry 4");
    expect_error("{" + g + R"(, "instances": [{"geometry": "teapot"}]})", "instances[0].geometry: no geometry named");
    expect_error("{" + g + R"(, "instances": [{"geometry": 0}, {"geometry": 0}, {"geometry": 0},
                 {"geometry": 0, "transform": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 0, 0]]}]})",
                 "instances[3].transform: singular");
    expect_error("{" + g + R"(, "instances": [{"geometry": 0, "transform": [[1, 0, 0, 0], [0, 1, 0], [0, 0, 1, 0]]}]})",
                 "instances[0].transform[1]: expected 4 numbers");
    expect_error("{" + g + R"(, "instances": [{"geometry": 0, "scale": 0}]})", "instances[0].transform: singular");
    expect_error("{" + g + R"(, "instances": [{"geometry": 0, "translate": [1e39, 0, 0]}]})",
                 "instances[0].translate[0]: not a finite float");
    expect_error("{" + g + R"(, "planes": [{"point": [0, 0, 0], "normal": [0, 0, 0]}]})", "planes[0].normal: zero");
    expect_error(R"({"geometries": [{"boxes": [{"min": [1, 0, 0], "max": [0, 1, 1]}]}]})",
                 "geometries[0].boxes[0]: min > max");
    expect_error(R"({"geometries": [{"mesh": "no/such/file.ply"}]})", "geometries[0].mesh: ");
    expect_error(R"({"geometries": [{"spheres": [], "boxes": []}]})", "geometries[0]: needs exactly one");
    expect_error(R"({"geometries": [1, 2)", "not valid JSON");
    expect_error(R"({"geometries": [{"spheres": [{"center": [0, 0, 0], "radius": NaN}]}]})", "not valid JSON");
    expect_error(R"([1, 2])", "(root): expected an object");
    // Bounds past the float range: an instance scaled past it, a sphere whose center + radius is.
    expect_error(R"({"geometries": [{"boxes": [{"min": [-3e38, -3e38, -3e38], "max": [3e38, 3e38, 3e38]}]}],
                     "instances": [{"geometry": 0}, {"geometry": 0}, {"geometry": 0, "scale": 1e30}]})",
                 "instances[2].transform: takes geometries[0] beyond the float range");
    expect_error(R"({"geometries": [{"spheres": [{"center": [3e38, 0, 0], "radius": 3e38}]}]})",
                 "geometries[0].spheres[0]: its bounds (center +- radius) exceed the float range");
    expect_error(R"({"geometries": [{"spheres": [{"center": [0, 0, 0], "radius": 1, "radius": -1}]}]})",
                 "geometries[0].spheres[0]: duplicate key 'radius'");
}

TEST(SceneBuiltin, InstancesAreDeterministicAndInvertible) {
    const Mesh ico = icosphere(1);
    const SceneDesc a = instances_scene(ico, 50), b = instances_scene(ico, 50);
    ASSERT_EQ(a.instances.size(), 50u);
    for (std::size_t i = 0; i < 50; ++i) {
        EXPECT_EQ(a.instances[i].transform.m, b.instances[i].transform.m);
        EXPECT_NO_THROW(invert(a.instances[i].transform));
    }
    EXPECT_NE(a.instances[0].transform.m, a.instances[1].transform.m);
    EXPECT_NO_THROW(validate(a));
}

TEST(SceneBuiltin, NamesAndSpheres) {
    EXPECT_TRUE(is_builtin_scene("instances-16"));
    EXPECT_TRUE(is_builtin_scene("spheres-1000"));
    EXPECT_TRUE(is_builtin_scene("room"));
    // A family's name with a bad count is still a built-in name (builtin_scene reports the count) ...
    EXPECT_TRUE(is_builtin_scene("instances-"));
    EXPECT_TRUE(is_builtin_scene("instances-0"));
    EXPECT_TRUE(is_builtin_scene("spheres-0"));
    EXPECT_TRUE(is_builtin_scene("spheres--5"));
    EXPECT_TRUE(is_builtin_scene("spheres-x"));
    // ... but a path is not.
    EXPECT_FALSE(is_builtin_scene("spheres-3.ply"));
    EXPECT_FALSE(is_builtin_scene("dir/instances-3"));
    EXPECT_FALSE(is_builtin_scene("spheres"));
    EXPECT_FALSE(is_builtin_scene("room.obj"));
    const SceneDesc s = builtin_scene("spheres-1000");
    ASSERT_EQ(std::get<SphereSet>(s.geometries[0]).spheres.size(), 1000u);
    for (const Sphere& sp : std::get<SphereSet>(s.geometries[0]).spheres) {
        EXPECT_GE(sp.radius, 0.1f * 0.1f - 1e-6f);
        EXPECT_LE(sp.radius, 0.5f * 0.1f + 1e-6f);
    }
    EXPECT_THROW(builtin_scene("spheres-20000000"), Error);
}

// "info --scene spheres-0" said "unknown mesh format '(none)'": a family's name
// with a bad count gets the family's message, from every loader of scene names.
TEST(SceneBuiltin, BadCountNamesTheBuiltIn) {
    for (const char* name : {"instances-0", "spheres-0", "spheres--5", "spheres-x", "instances-", "spheres-20000000"}) {
        const std::string base = std::string(name).substr(0, std::string(name).find('-'));
        for (bool desc : {true, false}) {
            try {
                desc ? load_scene_desc(name) : builtin_scene(name);
                ADD_FAILURE() << name << " loaded";
            } catch (const Error& e) {
                EXPECT_NE(std::string(e.what()).find("scene '" + std::string(name) + "': the count N of " + base +
                                                     "-N must be a whole number from 1 to 10000000"),
                          std::string::npos)
                    << e.what();
            }
        }
    }
}

TEST(SceneBuiltin, RoomWhenCached) {
    if (!is_cached("bunny") || !is_cached("teapot")) GTEST_SKIP() << "bunny/teapot not cached";
    const SceneDesc s = room_scene();
    EXPECT_EQ(s.planes.size(), 4u);
    EXPECT_EQ(s.instances.size(), 5u);
    EXPECT_NO_THROW(validate(s));
}

}  // namespace
}  // namespace simdbvh::workloads
