#pragma once
// Vec3: three floats, no SIMD, the value type of every public interface.
#include <cmath>
#include <cstdint>

namespace simdbvh {

struct Vec3 {
    float x = 0, y = 0, z = 0;
    constexpr float operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    constexpr float& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
};
static_assert(sizeof(Vec3) == 12);

constexpr Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
constexpr Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
constexpr Vec3 operator*(Vec3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }
constexpr Vec3 operator*(float s, Vec3 a) { return {a.x * s, a.y * s, a.z * s}; }
constexpr bool operator==(Vec3 a, Vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }
constexpr float dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3 cross(Vec3 a, Vec3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
inline float length(Vec3 a) { return std::sqrt(dot(a, a)); }
inline Vec3 normalize(Vec3 a) { return a * (1.0f / length(a)); }
// NaN-discarding min/max with the semantics of x86 minps/maxps: the second
// operand is returned when either is NaN, so put the value that may be NaN first.
constexpr float min_ps(float a, float b) { return a < b ? a : b; }
constexpr float max_ps(float a, float b) { return a > b ? a : b; }
constexpr Vec3 vmin(Vec3 a, Vec3 b) { return {min_ps(a.x, b.x), min_ps(a.y, b.y), min_ps(a.z, b.z)}; }
constexpr Vec3 vmax(Vec3 a, Vec3 b) { return {max_ps(a.x, b.x), max_ps(a.y, b.y), max_ps(a.z, b.z)}; }
inline bool is_finite(Vec3 a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }

}  // namespace simdbvh
