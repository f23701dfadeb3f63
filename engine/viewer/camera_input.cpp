// Mouse -> orbit camera.
#include "camera_input.h"

#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>

namespace ngi::view {

void CameraController::frame(glm::vec3 boundsMin, glm::vec3 boundsMax, float aspect)
{
    home_ = vk::frameBounds(boundsMin, boundsMax, 30.0f, 25.0f, aspect, 1.1f);
    radius_ = std::max(0.5f * glm::length(boundsMax - boundsMin), 1e-3f);
    camera_ = home_;
    updateClipPlanes();
    home_ = camera_;
}

void CameraController::updateClipPlanes()
{
    camera_.nearPlane = std::max(camera_.distance - radius_ * 1.5f, camera_.distance * 1e-3f);
    camera_.farPlane = camera_.distance + radius_ * 1.5f;
}

void CameraController::update(const MouseInput& mouse, float viewportHeight)
{
    if (dragButton_ >= 0 && !mouse.down[dragButton_]) dragButton_ = -1;
    if (dragButton_ < 0 && !mouse.overUi)
        for (int b = 0; b < 3; ++b)
            if (mouse.pressed[b]) dragButton_ = b;

    if (dragButton_ == 0) {  // orbit
        camera_.yawDegrees -= mouse.delta.x * 0.4f;
        camera_.pitchDegrees = std::clamp(camera_.pitchDegrees + mouse.delta.y * 0.4f, -89.0f, 89.0f);
    } else if (dragButton_ > 0) {  // pan in the view plane, so the point under the cursor follows it
        const glm::mat4 view = camera_.view();
        const glm::vec3 right(view[0][0], view[1][0], view[2][0]), up(view[0][1], view[1][1], view[2][1]);
        const float unitsPerPixel = 2.0f * camera_.distance * std::tan(glm::radians(camera_.fovYDegrees) * 0.5f) /
            std::max(viewportHeight, 1.0f);
        camera_.target += (-mouse.delta.x * right + mouse.delta.y * up) * unitsPerPixel;
    }
    if (!mouse.overUi && mouse.wheel != 0.0f) {
        camera_.distance =
            std::clamp(camera_.distance * std::pow(0.88f, mouse.wheel), radius_ * 0.02f, radius_ * 60.0f);
        updateClipPlanes();
    }
}

glm::mat4 CameraController::viewProjection(VkExtent2D extent, float leftMargin) const
{
    const float w = float(std::max(extent.width, 1u)), h = float(std::max(extent.height, 1u));
    const float regionW = std::max(w - leftMargin, 1.0f);
    // Squeeze NDC x into the region right of the panel: x' = x * regionW / w + leftMargin / w
    // (multiplied by clip w, so it is a translation in the matrix's last column).
    glm::mat4 toRegion(1.0f);
    toRegion[0][0] = regionW / w;
    toRegion[3][0] = leftMargin / w;
    return toRegion * camera_.viewProjection(regionW / h);
}

}  // namespace ngi::view
