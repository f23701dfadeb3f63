// ngi-view: the GLFW window and its Vulkan surface. Knows nothing about rendering: it opens
// the window system (or says clearly that there is none), reports the framebuffer size and
// collects files dropped onto the window.
#pragma once

#include <vulkan/vulkan.h>

#include <exception>
#include <string>
#include <vector>

struct GLFWwindow;

namespace ngi::view {

// Thrown when no window system is reachable (no DISPLAY, no X server): the caller prints it
// with the hint to use ngi-render for headless capture.
struct NoDisplayError : std::exception {
    explicit NoDisplayError(std::string m) : message(std::move(m)) {}
    const char* what() const noexcept override { return message.c_str(); }
    std::string message;
};

class Window {
public:
    // Initializes GLFW and opens a width x height window without a client API.
    // NoDisplayError when no display is available, ngi::Error for other failures
    // (e.g. no Vulkan loader).
    Window(int width, int height, const std::string& title);
    ~Window();
    Window(const Window&) = delete;
    Window& operator=(const Window&) = delete;

    // The instance extensions the window system needs (VK_KHR_surface + the platform's).
    static std::vector<std::string> requiredInstanceExtensions();
    // Whether `family` of `device` can present to this window system.
    static bool presentationSupport(VkInstance instance, VkPhysicalDevice device, uint32_t family);

    // Creates the VkSurfaceKHR (owned by the caller, destroy before the instance).
    VkSurfaceKHR createSurface(VkInstance instance) const;

    GLFWwindow* handle() const { return window_; }
    bool shouldClose() const;
    void requestClose();
    // Framebuffer size in pixels; 0 x 0 while minimized.
    VkExtent2D framebufferSize() const;
    void setSize(int width, int height);
    void setTitle(const std::string& title);
    // Files dropped since the last call, oldest first.
    std::vector<std::string> takeDroppedFiles();

private:
    GLFWwindow* window_ = nullptr;
    std::vector<std::string> dropped_;
    friend void onDrop(GLFWwindow*, int, const char**);
};

}  // namespace ngi::view
