// Dear ImGui 1.86 setup with the GLFW and Vulkan backends.
#include "imgui_layer.h"

#include "presenter.h"

#include "ngi/engine/vk_check.h"
#include "ngi/error.h"

#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_vulkan.h>

#include <algorithm>

namespace ngi::view {
namespace {

void checkImGuiVulkan(VkResult result)
{
    if (result < 0) vk::throwVulkanError(result, "ImGui Vulkan backend", __FILE__, __LINE__);
}

}  // namespace

ImGuiLayer::ImGuiLayer(GLFWwindow* window, const vk::Context& context, const Presenter& presenter)
    : device_(context.device)
{
    VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 8};
    VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    poolInfo.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
    poolInfo.maxSets = 8;
    poolInfo.poolSizeCount = 1;
    poolInfo.pPoolSizes = &size;
    NGI_VK_CHECK(vkCreateDescriptorPool(device_, &poolInfo, nullptr, &pool_));

    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;  // no imgui.ini in the working directory; the layout is fixed
    ImGui::StyleColorsDark();
    ImGui::GetStyle().WindowRounding = 0.0f;
    if (!ImGui_ImplGlfw_InitForVulkan(window, true)) throw Error("Dear ImGui: the GLFW backend failed to initialize");

    ImGui_ImplVulkan_InitInfo info{};
    info.Instance = context.instance;
    info.PhysicalDevice = context.physicalDevice;
    info.Device = context.device;
    info.QueueFamily = context.queueFamily;
    info.Queue = context.queue;
    info.DescriptorPool = pool_;
    info.Subpass = 0;
    info.MinImageCount = presenter.minImageCount();
    // The backend rotates its vertex buffers over ImageCount frames; any count >= the
    // frames in flight is safe because a frame slot is reused only after its fence.
    info.ImageCount = std::max(presenter.imageCount(), Presenter::kFramesInFlight);
    info.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
    info.CheckVkResultFn = checkImGuiVulkan;
    if (!ImGui_ImplVulkan_Init(&info, presenter.overlayPass()))
        throw Error("Dear ImGui: the Vulkan backend failed to initialize");
    context.submitAndWait([](VkCommandBuffer cmd) { ImGui_ImplVulkan_CreateFontsTexture(cmd); });
    ImGui_ImplVulkan_DestroyFontUploadObjects();
}

ImGuiLayer::~ImGuiLayer()
{
    vkDeviceWaitIdle(device_);
    ImGui_ImplVulkan_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    vkDestroyDescriptorPool(device_, pool_, nullptr);
}

void ImGuiLayer::newFrame()
{
    ImGui_ImplVulkan_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
}

void ImGuiLayer::record(VkCommandBuffer cmd)
{
    if (ImDrawData* data = ImGui::GetDrawData()) ImGui_ImplVulkan_RenderDrawData(data, cmd);
}

}  // namespace ngi::view
