// ngi engine: headless rendering into an offscreen colour + depth target and read-back of
// the pixels (ngi-render, tests). MSAA targets are resolved before read-back.
#pragma once

#include "ngi/engine/renderer.h"
#include "ngi/engine/resources.h"

#include <glm/vec4.hpp>

#include <cstdint>
#include <functional>
#include <vector>

namespace ngi::vk {

class OffscreenTarget {
public:
    // A width x height target with the renderer's formats and sample count.
    OffscreenTarget(const Renderer& renderer, uint32_t width, uint32_t height);
    OffscreenTarget(const OffscreenTarget&) = delete;
    OffscreenTarget& operator=(const OffscreenTarget&) = delete;

    // Clears to `clear`, records `draw` inside dynamic rendering, submits, waits and returns
    // the RGBA8 pixels, row-major from the top-left.
    std::vector<uint8_t> render(const std::function<void(VkCommandBuffer)>& draw, glm::vec4 clear,
                                const std::function<void(VkCommandBuffer)>& beforeRendering = {});

    VkExtent2D extent() const { return {width_, height_}; }

private:
    const Renderer& renderer_;
    uint32_t width_, height_;
    UniqueImage color_, resolve_, depth_;  // owners: a constructor that throws frees what it made
    UniqueBuffer readback_;
};

}  // namespace ngi::vk
