// The scene camera (scene_desc.h): the default camera over a scene's bounded
// part, kept inside the planes that face its centre.
#include <algorithm>
#include <cmath>

#include "simdbvh/workloads/scene_desc.h"

namespace simdbvh::workloads {

Camera scene_camera(const SceneDesc& desc, int w, int h) {
    Aabb box = world_bounds(desc);
    if (box.is_empty()) box = Aabb{{-1, -1, -1}, {1, 1, 1}};  // planes only
    Camera cam = default_camera(box, w, h);
    const Vec3 c = box.center();
    float keep = 1.0f;  // eye = c + keep * (eye - c)
    for (const Plane& p : desc.planes) {
        const float dc = dot(c - p.point, p.normal), de = dot(cam.eye - p.point, p.normal);
        if (dc > 0 && de <= 0) keep = std::min(keep, 0.9f * dc / (dc - de));
    }
    cam.eye = c + (cam.eye - c) * keep;
    return cam;
}

std::vector<Ray> scene_camera_rays(const SceneDesc& desc, std::size_t n) {
    const int side = std::max(16, int(std::lround(std::sqrt(double(n)))));
    return primary_rays(scene_camera(desc, side, side));
}

}  // namespace simdbvh::workloads
