// GLFW window, Vulkan surface, drag-and-drop.
#include "window.h"

#include "ngi/engine/vk_check.h"
#include "ngi/error.h"

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include <algorithm>
#include <cstdlib>

namespace ngi::view {
namespace {

std::string lastGlfwError;

void onGlfwError(int code, const char* description)
{
    lastGlfwError =
        std::string(description ? description : "unknown error") + " (GLFW error " + std::to_string(code) + ")";
}

}  // namespace

void onDrop(GLFWwindow* window, int count, const char** paths)
{
    auto* self = static_cast<Window*>(glfwGetWindowUserPointer(window));
    for (int i = 0; i < count; ++i) self->dropped_.emplace_back(paths[i]);
}

Window::Window(int width, int height, const std::string& title)
{
    glfwSetErrorCallback(onGlfwError);
    const char* display = std::getenv("DISPLAY");
    const char* wayland = std::getenv("WAYLAND_DISPLAY");
    if ((!display || !*display) && (!wayland || !*wayland))
        throw NoDisplayError("no display: neither DISPLAY nor WAYLAND_DISPLAY is set");
    if (!glfwInit())
        throw NoDisplayError("cannot open the display '" + std::string(display ? display : "") + "': " + lastGlfwError);
    if (!glfwVulkanSupported()) {
        glfwTerminate();
        throw Error("GLFW found no Vulkan loader (install libvulkan1 and a driver, e.g. mesa-vulkan-drivers)");
    }
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
    window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
    if (!window_) {
        glfwTerminate();
        throw Error("cannot create a " + std::to_string(width) + "x" + std::to_string(height) +
                    " window: " + lastGlfwError);
    }
    glfwSetWindowUserPointer(window_, this);
    glfwSetDropCallback(window_, onDrop);
}

Window::~Window()
{
    if (window_) glfwDestroyWindow(window_);
    glfwTerminate();
}

std::vector<std::string> Window::requiredInstanceExtensions()
{
    uint32_t count = 0;
    const char** names = glfwGetRequiredInstanceExtensions(&count);
    if (!names) throw Error("the window system offers no Vulkan surface extension: " + lastGlfwError);
    return std::vector<std::string>(names, names + count);
}

bool Window::presentationSupport(VkInstance instance, VkPhysicalDevice device, uint32_t family)
{
    return glfwGetPhysicalDevicePresentationSupport(instance, device, family) == GLFW_TRUE;
}

VkSurfaceKHR Window::createSurface(VkInstance instance) const
{
    VkSurfaceKHR surface = VK_NULL_HANDLE;
    NGI_VK_CHECK(glfwCreateWindowSurface(instance, window_, nullptr, &surface));
    return surface;
}

bool Window::shouldClose() const { return glfwWindowShouldClose(window_); }
void Window::requestClose() { glfwSetWindowShouldClose(window_, GLFW_TRUE); }

VkExtent2D Window::framebufferSize() const
{
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_, &w, &h);
    if (glfwGetWindowAttrib(window_, GLFW_ICONIFIED)) w = h = 0;
    return {uint32_t(std::max(w, 0)), uint32_t(std::max(h, 0))};
}

void Window::setSize(int width, int height) { glfwSetWindowSize(window_, width, height); }
void Window::setTitle(const std::string& title) { glfwSetWindowTitle(window_, title.c_str()); }

std::vector<std::string> Window::takeDroppedFiles()
{
    std::vector<std::string> out;
    out.swap(dropped_);
    return out;
}

}  // namespace ngi::view
