// Test helper: cameras orbiting a normalized asset's centre and the adaptive views they make
// (ngi/adaptive_lod.h AdaptiveView), shared by the adaptive draw's suites.
#pragma once

#include "ngi/adaptive_lod.h"
#include "ngi/engine/camera.h"

namespace ngi::test {

// An orbit camera around (0.5, 0.5, 0.5): `yaw` and `pitch` in degrees, `distance` in units.
inline vk::OrbitCamera orbitCameraAt(float yaw, float pitch, float distance)
{
    vk::OrbitCamera camera;
    camera.target = glm::vec3(0.5f);
    camera.distance = distance;
    camera.yawDegrees = yaw;
    camera.pitchDegrees = pitch;
    return camera;
}

// The camera's adaptive view of a square viewport `viewportHeight` pixels high within `pixels`.
inline AdaptiveView cameraView(const vk::OrbitCamera& camera, float viewportHeight, float pixels, bool cull)
{
    AdaptiveView view;
    view.camera = true;
    view.clipFromNormalized = camera.viewProjection(1.0f);
    view.eye = camera.eye();
    view.viewportHeight = viewportHeight;
    view.maxErrorPixels = pixels;
    view.cull = cull;
    return view;
}

}  // namespace ngi::test
