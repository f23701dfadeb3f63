// ngi-view: the orbit camera driven by the mouse: orbit with the left button, pan with the
// middle or right button, zoom with the wheel; reset to the framing of the asset. The 3D
// view occupies the window right of the panel (an off-centre projection, because
// Renderer::recordDraw always sets the viewport to the whole extent).
#pragma once

#include "ngi/engine/camera.h"

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <vulkan/vulkan.h>

namespace ngi::view {

struct MouseInput {
    glm::vec2 delta{0.0f};  // cursor motion since the last frame, pixels
    float wheel = 0.0f;     // wheel steps since the last frame (+ = away from the user)
    bool down[3] = {};      // left, right, middle held
    bool pressed[3] = {};   // went down this frame
    bool overUi = false;    // the UI wants the mouse: no new drags, no zoom
};

class CameraController {
public:
    // Frames the box for a view of aspect `aspect` and makes that the reset position.
    void frame(glm::vec3 boundsMin, glm::vec3 boundsMax, float aspect);
    void reset() { camera_ = home_; }
    void update(const MouseInput& mouse, float viewportHeight);

    const vk::OrbitCamera& camera() const { return camera_; }
    // Clip space for a view occupying x in [leftMargin, extent.width) of the framebuffer.
    glm::mat4 viewProjection(VkExtent2D extent, float leftMargin) const;
    float distance() const { return camera_.distance; }
    bool dragging() const { return dragButton_ >= 0; }

private:
    void updateClipPlanes();
    vk::OrbitCamera camera_, home_;
    float radius_ = 1.0f;
    int dragButton_ = -1;
};

}  // namespace ngi::view
