// ngi engine: an orbit camera that frames a bounding box (Vulkan clip conventions:
// depth 0..1, y down in framebuffer space).
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace ngi::vk {

struct OrbitCamera {
    glm::vec3 target{0.5f};
    float distance = 2.0f;
    float yawDegrees = 30.0f;    // around +y
    float pitchDegrees = 20.0f;  // above the horizon
    float fovYDegrees = 35.0f;
    float nearPlane = 0.01f, farPlane = 100.0f;

    glm::vec3 eye() const;
    glm::mat4 view() const;
    glm::mat4 projection(float aspect) const;
    glm::mat4 viewProjection(float aspect) const { return projection(aspect) * view(); }
};

// A camera looking at the box's centre from yaw/pitch, far enough that the box's bounding
// sphere fits the view (with `margin` of slack) for the given aspect ratio.
OrbitCamera frameBounds(glm::vec3 boundsMin, glm::vec3 boundsMax, float yawDegrees, float pitchDegrees, float aspect,
                        float margin = 1.12f);

}  // namespace ngi::vk
