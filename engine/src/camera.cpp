// Orbit camera and bounding-box framing.
#include "ngi/engine/camera.h"

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>

namespace ngi::vk {

glm::vec3 OrbitCamera::eye() const
{
    const float yaw = glm::radians(yawDegrees), pitch = glm::radians(pitchDegrees);
    const glm::vec3 dir(std::cos(pitch) * std::sin(yaw), std::sin(pitch), std::cos(pitch) * std::cos(yaw));
    return target + distance * dir;
}

glm::mat4 OrbitCamera::view() const
{
    const glm::vec3 e = eye();
    const glm::vec3 up = std::abs(pitchDegrees) > 89.0f ? glm::vec3(0, 0, -1) : glm::vec3(0, 1, 0);
    return glm::lookAtRH(e, target, up);
}

glm::mat4 OrbitCamera::projection(float aspect) const
{
    glm::mat4 p = glm::perspectiveRH_ZO(glm::radians(fovYDegrees), aspect, nearPlane, farPlane);
    p[1][1] *= -1.0f;  // Vulkan's framebuffer y points down
    return p;
}

OrbitCamera frameBounds(glm::vec3 boundsMin, glm::vec3 boundsMax, float yawDegrees, float pitchDegrees, float aspect,
                        float margin)
{
    OrbitCamera c;
    c.target = 0.5f * (boundsMin + boundsMax);
    c.yawDegrees = yawDegrees;
    c.pitchDegrees = pitchDegrees;
    // Distance at which every corner of the box projects inside the view (with `margin`):
    // a corner at (x, y) across and z towards the camera fits when d >= z + |x| / tan(halfX).
    const float halfY = glm::radians(c.fovYDegrees) * 0.5f;
    const float tanY = std::tan(halfY), tanX = tanY * aspect;
    const glm::vec3 forward = glm::normalize(c.eye() - c.target);  // c.distance is still the default here
    const glm::mat4 view = c.view();
    const glm::vec3 right(view[0][0], view[1][0], view[2][0]), up(view[0][1], view[1][1], view[2][1]);
    float distance = 1e-6f, radius = 0.0f;
    for (int i = 0; i < 8; ++i) {
        const glm::vec3 corner((i & 1) ? boundsMax.x : boundsMin.x, (i & 2) ? boundsMax.y : boundsMin.y,
                               (i & 4) ? boundsMax.z : boundsMin.z);
        const glm::vec3 r = corner - c.target;
        const float z = glm::dot(r, forward);
        distance = std::max({distance, z + std::abs(glm::dot(r, right)) * margin / tanX,
                             z + std::abs(glm::dot(r, up)) * margin / tanY});
        radius = std::max(radius, glm::length(r));
    }
    c.distance = distance;
    c.nearPlane = std::max(c.distance - radius * 1.5f, c.distance * 1e-3f);
    c.farPlane = c.distance + radius * 1.5f;
    return c;
}

}  // namespace ngi::vk
