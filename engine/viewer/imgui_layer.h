// ngi-view: Dear ImGui (Debian's 1.86) on GLFW and Vulkan. The 1.86 Vulkan backend draws
// only inside a VkRenderPass, so it is initialized with the presenter's overlay pass.
#pragma once

#include "ngi/engine/context.h"

#include <vulkan/vulkan.h>

struct GLFWwindow;

namespace ngi::view {

class Presenter;

class ImGuiLayer {
public:
    // Creates the ImGui context, installs the GLFW callbacks (chaining ones set before) and
    // uploads the font. ngi::Error on failure.
    ImGuiLayer(GLFWwindow* window, const vk::Context& context, const Presenter& presenter);
    ~ImGuiLayer();
    ImGuiLayer(const ImGuiLayer&) = delete;
    ImGuiLayer& operator=(const ImGuiLayer&) = delete;

    void newFrame();
    // Records the draw data of the last ImGui::Render() (inside the overlay pass).
    void record(VkCommandBuffer cmd);

private:
    VkDevice device_;
    VkDescriptorPool pool_ = VK_NULL_HANDLE;
};

}  // namespace ngi::view
