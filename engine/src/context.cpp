// Vulkan instance/device creation and selection, validation messages, one-shot submits.
#include "ngi/engine/context.h"

#include "ngi/engine/resources.h"
#include "ngi/engine/vk_check.h"
#include "ngi/error.h"
#include "ngi_shared.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <cstring>

namespace ngi::vk {

// A table of macro cases, laid out by hand:
// clang-format off
const char* resultName(VkResult r)
{
    switch (r) {
#define NGI_CASE(x) case x: return #x;
        NGI_CASE(VK_SUCCESS) NGI_CASE(VK_NOT_READY) NGI_CASE(VK_TIMEOUT) NGI_CASE(VK_EVENT_SET)
        NGI_CASE(VK_EVENT_RESET) NGI_CASE(VK_INCOMPLETE) NGI_CASE(VK_ERROR_OUT_OF_HOST_MEMORY)
        NGI_CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY) NGI_CASE(VK_ERROR_INITIALIZATION_FAILED)
        NGI_CASE(VK_ERROR_DEVICE_LOST) NGI_CASE(VK_ERROR_MEMORY_MAP_FAILED) NGI_CASE(VK_ERROR_LAYER_NOT_PRESENT)
        NGI_CASE(VK_ERROR_EXTENSION_NOT_PRESENT) NGI_CASE(VK_ERROR_FEATURE_NOT_PRESENT)
        NGI_CASE(VK_ERROR_INCOMPATIBLE_DRIVER) NGI_CASE(VK_ERROR_TOO_MANY_OBJECTS)
        NGI_CASE(VK_ERROR_FORMAT_NOT_SUPPORTED) NGI_CASE(VK_ERROR_FRAGMENTED_POOL) NGI_CASE(VK_ERROR_UNKNOWN)
        NGI_CASE(VK_ERROR_OUT_OF_POOL_MEMORY) NGI_CASE(VK_ERROR_INVALID_EXTERNAL_HANDLE)
        NGI_CASE(VK_ERROR_FRAGMENTATION) NGI_CASE(VK_ERROR_INVALID_OPAQUE_CAPTURE_ADDRESS)
        NGI_CASE(VK_PIPELINE_COMPILE_REQUIRED) NGI_CASE(VK_ERROR_SURFACE_LOST_KHR)
        NGI_CASE(VK_ERROR_NATIVE_WINDOW_IN_USE_KHR) NGI_CASE(VK_SUBOPTIMAL_KHR) NGI_CASE(VK_ERROR_OUT_OF_DATE_KHR)
        NGI_CASE(VK_ERROR_INCOMPATIBLE_DISPLAY_KHR) NGI_CASE(VK_ERROR_VALIDATION_FAILED_EXT)
#undef NGI_CASE
    default: return "VkResult(unknown)";
    }
}
// clang-format on

void throwVulkanError(VkResult result, const char* call, const char* file, int line)
{
    const char* base = std::strrchr(file, '/');
    throw Error(std::string(base ? base + 1 : file) + ":" + std::to_string(line) + ": " + call + " failed with " +
                resultName(result));
}

VKAPI_ATTR VkBool32 VKAPI_CALL onValidationMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                   VkDebugUtilsMessageTypeFlagsEXT,
                                                   const VkDebugUtilsMessengerCallbackDataEXT* data, void* user)
{
    auto* context = static_cast<Context*>(user);
    const char* level = severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT ? "error" : "warning";
    std::lock_guard lock(context->messagesMutex_);
    context->messages_.push_back(std::string("validation ") + level + ": " + (data->pMessage ? data->pMessage : ""));
    return VK_FALSE;
}

namespace {

bool envFlag(const char* name)
{
    const char* v = std::getenv(name);
    return v && *v && std::strcmp(v, "0") != 0;
}

std::string lower(std::string s)
{
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

const char* typeName(VkPhysicalDeviceType t)
{
    switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "CPU";
    default: return "other";
    }
}

int typeScore(VkPhysicalDeviceType t)
{
    switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 4;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 3;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return 1;
    default: return 0;
    }
}

bool hasLayer(const char* name)
{
    uint32_t count = 0;
    vkEnumerateInstanceLayerProperties(&count, nullptr);
    std::vector<VkLayerProperties> layers(count);
    vkEnumerateInstanceLayerProperties(&count, layers.data());
    for (const auto& l : layers)
        if (std::strcmp(l.layerName, name) == 0) return true;
    return false;
}

VkInstance createInstance(const std::vector<const char*>& layers, const std::vector<const char*>& extensions)
{
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "ngi";
    app.pEngineName = "ngi";
    app.apiVersion = VK_API_VERSION_1_3;
    VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    info.pApplicationInfo = &app;
    info.enabledLayerCount = uint32_t(layers.size());
    info.ppEnabledLayerNames = layers.data();
    info.enabledExtensionCount = uint32_t(extensions.size());
    info.ppEnabledExtensionNames = extensions.data();
    VkInstance instance = VK_NULL_HANDLE;
    const VkResult r = vkCreateInstance(&info, nullptr, &instance);
    if (r == VK_ERROR_INCOMPATIBLE_DRIVER)
        throw Error("no Vulkan driver found (VK_ERROR_INCOMPATIBLE_DRIVER): install a GPU driver, or "
                    "mesa-vulkan-drivers for the lavapipe CPU device");
    if (r != VK_SUCCESS) throw Error(std::string("cannot create a Vulkan instance: ") + resultName(r));
    return instance;
}

int graphicsComputeFamily(VkInstance instance, VkPhysicalDevice pd, const ContextOptions* options)
{
    uint32_t count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &count, nullptr);
    std::vector<VkQueueFamilyProperties> families(count);
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &count, families.data());
    for (uint32_t i = 0; i < count; ++i) {
        const VkQueueFlags need = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
        if ((families[i].queueFlags & need) != need) continue;
        if (options && options->queueFamilyFilter && !options->queueFamilyFilter(instance, pd, i)) continue;
        return int(i);
    }
    return -1;
}

std::vector<DeviceInfo> describeDevices(VkInstance instance, std::vector<VkPhysicalDevice>& handles,
                                        const ContextOptions* options)
{
    uint32_t count = 0;
    vkEnumeratePhysicalDevices(instance, &count, nullptr);
    handles.resize(count);
    vkEnumeratePhysicalDevices(instance, &count, handles.data());
    std::vector<DeviceInfo> infos;
    for (uint32_t i = 0; i < count; ++i) {
        VkPhysicalDeviceProperties p;
        vkGetPhysicalDeviceProperties(handles[i], &p);
        DeviceInfo d;
        d.index = i;
        d.name = p.deviceName;
        d.type = typeName(p.deviceType);
        d.apiVersion = p.apiVersion;
        d.suitable = true;
        if (p.apiVersion < VK_API_VERSION_1_3) {
            d.suitable = false;
            d.unsuitableBecause = "needs Vulkan 1.3";
        } else if (graphicsComputeFamily(instance, handles[i], options) < 0) {
            d.suitable = false;
            d.unsuitableBecause = "no graphics+compute queue" +
                std::string(options && options->queueFamilyFilter ? " with presentation support" : "");
        }
        infos.push_back(d);
    }
    return infos;
}

}  // namespace

std::vector<DeviceInfo> listDevices()
{
    VkInstance instance = createInstance({}, {});
    std::vector<VkPhysicalDevice> handles;
    auto infos = describeDevices(instance, handles, nullptr);
    vkDestroyInstance(instance, nullptr);
    return infos;
}

std::unique_ptr<Context> Context::create(const ContextOptions& options)
{
    std::unique_ptr<Context> c(new Context());
    c->owns_ = true;
    const bool validation = options.validation || envFlag("NGI_VALIDATION");
    std::vector<const char*> layers, extensions;
    for (const auto& e : options.instanceExtensions) extensions.push_back(e.c_str());
    if (validation) {
        if (!hasLayer("VK_LAYER_KHRONOS_validation"))
            throw Error("Vulkan validation was requested but VK_LAYER_KHRONOS_validation is not installed "
                        "(Debian package vulkan-validationlayers)");
        layers.push_back("VK_LAYER_KHRONOS_validation");
        extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    }
    c->instance = createInstance(layers, extensions);

    if (validation) {
        VkDebugUtilsMessengerCreateInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
        info.messageSeverity =
            VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
        info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
            VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
        info.pfnUserCallback = onValidationMessage;
        info.pUserData = c.get();
        auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(c->instance, "vkCreateDebugUtilsMessengerEXT"));
        if (!create) throw Error("Vulkan validation: vkCreateDebugUtilsMessengerEXT is unavailable");
        NGI_VK_CHECK(create(c->instance, &info, nullptr, &c->messenger_));
    }

    std::vector<VkPhysicalDevice> handles;
    const auto infos = describeDevices(c->instance, handles, &options);
    if (infos.empty())
        throw Error("no Vulkan device found: install a GPU driver, or mesa-vulkan-drivers for the lavapipe CPU device");

    std::string selector = options.device;
    if (selector.empty())
        if (const char* env = std::getenv("NGI_DEVICE")) selector = env;
    int chosen = -1;
    if (!selector.empty()) {
        const bool isIndex =
            std::all_of(selector.begin(), selector.end(), [](unsigned char ch) { return std::isdigit(ch); });
        for (const auto& d : infos)
            if (isIndex ? d.index == uint32_t(std::stoul(selector))
                        : lower(d.name).find(lower(selector)) != std::string::npos) {
                chosen = int(d.index);
                break;
            }
        if (chosen < 0) {
            std::string names;
            for (const auto& d : infos) names += (names.empty() ? "" : ", ") + std::to_string(d.index) + ": " + d.name;
            throw Error("Vulkan device '" + selector + "' not found (devices: " + names + ")");
        }
        if (!infos[chosen].suitable)
            throw Error("Vulkan device '" + infos[chosen].name +
                        "' cannot run ngi: " + infos[chosen].unsuitableBecause);
    } else {
        int best = -1;
        for (const auto& d : infos) {
            if (!d.suitable) continue;
            VkPhysicalDeviceProperties p;
            vkGetPhysicalDeviceProperties(handles[d.index], &p);
            if (typeScore(p.deviceType) > best) {
                best = typeScore(p.deviceType);
                chosen = int(d.index);
            }
        }
        if (chosen < 0)
            throw Error("no Vulkan device can run ngi (" + infos[0].name + ": " + infos[0].unsuitableBecause + ")");
    }
    c->physicalDevice = handles[chosen];
    c->queueFamily = uint32_t(graphicsComputeFamily(c->instance, c->physicalDevice, &options));

    VkPhysicalDeviceFeatures supported{};
    vkGetPhysicalDeviceFeatures(c->physicalDevice, &supported);
    VkPhysicalDeviceVulkan13Features features13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
    features13.dynamicRendering = VK_TRUE;
    VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    features.pNext = &features13;
    features.features.pipelineStatisticsQuery = supported.pipelineStatisticsQuery;
    features.features.fillModeNonSolid = supported.fillModeNonSolid;
    features.features.independentBlend = supported.independentBlend;
    features.features.drawIndirectFirstInstance = supported.drawIndirectFirstInstance;
    c->pipelineStatistics = supported.pipelineStatisticsQuery;
    c->independentBlend = supported.independentBlend;
    c->drawIndirectFirstInstance = supported.drawIndirectFirstInstance;

    const float priority = 1.0f;
    VkDeviceQueueCreateInfo queueInfo{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    queueInfo.queueFamilyIndex = c->queueFamily;
    queueInfo.queueCount = 1;
    queueInfo.pQueuePriorities = &priority;
    std::vector<const char*> deviceExtensions;
    for (const auto& e : options.deviceExtensions) deviceExtensions.push_back(e.c_str());
    VkDeviceCreateInfo deviceInfo{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    deviceInfo.pNext = &features;
    deviceInfo.queueCreateInfoCount = 1;
    deviceInfo.pQueueCreateInfos = &queueInfo;
    deviceInfo.enabledExtensionCount = uint32_t(deviceExtensions.size());
    deviceInfo.ppEnabledExtensionNames = deviceExtensions.data();
    NGI_VK_CHECK(vkCreateDevice(c->physicalDevice, &deviceInfo, nullptr, &c->device));
    vkGetDeviceQueue(c->device, c->queueFamily, 0, &c->queue);
    vkGetPhysicalDeviceProperties(c->physicalDevice, &c->properties);
    vkGetPhysicalDeviceMemoryProperties(c->physicalDevice, &c->memoryProperties);

    VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    poolInfo.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT | VK_COMMAND_POOL_CREATE_TRANSIENT_BIT;
    poolInfo.queueFamilyIndex = c->queueFamily;
    NGI_VK_CHECK(vkCreateCommandPool(c->device, &poolInfo, nullptr, &c->commandPool_));
    return c;
}

namespace {

// The VkPhysicalDeviceFeatures a create info enables: pEnabledFeatures or a Features2 in its chain.
VkPhysicalDeviceFeatures enabledCoreFeatures(const VkDeviceCreateInfo& info)
{
    if (info.pEnabledFeatures) return *info.pEnabledFeatures;
    for (auto* s = static_cast<const VkBaseInStructure*>(info.pNext); s; s = s->pNext)
        if (s->sType == VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2)
            return reinterpret_cast<const VkPhysicalDeviceFeatures2*>(s)->features;
    return {};
}

bool dynamicRenderingEnabled(const VkDeviceCreateInfo& info)
{
    for (auto* s = static_cast<const VkBaseInStructure*>(info.pNext); s; s = s->pNext) {
        if (s->sType == VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES &&
            reinterpret_cast<const VkPhysicalDeviceVulkan13Features*>(s)->dynamicRendering)
            return true;
        if (s->sType == VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DYNAMIC_RENDERING_FEATURES &&
            reinterpret_cast<const VkPhysicalDeviceDynamicRenderingFeatures*>(s)->dynamicRendering)
            return true;
    }
    return false;
}

}  // namespace

std::vector<std::string> missingDeviceRequirements(const VkPhysicalDeviceProperties& properties,
                                                   VkQueueFlags familyFlags, const VkDeviceCreateInfo& enabled)
{
    std::vector<std::string> missing;
    if (properties.apiVersion < VK_API_VERSION_1_3)
        missing.push_back("Vulkan 1.3 (the device reports " +
                          std::to_string(VK_API_VERSION_MAJOR(properties.apiVersion)) + "." +
                          std::to_string(VK_API_VERSION_MINOR(properties.apiVersion)) + ")");
    if (!(familyFlags & VK_QUEUE_GRAPHICS_BIT) || !(familyFlags & VK_QUEUE_COMPUTE_BIT))
        missing.push_back(
            "a queue family with graphics and compute (the given family lacks " +
            std::string(!(familyFlags & VK_QUEUE_GRAPHICS_BIT) ? "graphics" : "") +
            (!(familyFlags & VK_QUEUE_GRAPHICS_BIT) && !(familyFlags & VK_QUEUE_COMPUTE_BIT) ? " and " : "") +
            (!(familyFlags & VK_QUEUE_COMPUTE_BIT) ? "compute" : "") + ")");
    if (!dynamicRenderingEnabled(enabled))
        missing.push_back("the dynamicRendering feature (VkPhysicalDeviceVulkan13Features::dynamicRendering in the "
                          "VkDeviceCreateInfo's pNext chain)");
    if (properties.limits.maxPushConstantsSize < sizeof(gpu::DrawPushConstants))
        missing.push_back("maxPushConstantsSize >= " + std::to_string(sizeof(gpu::DrawPushConstants)) +
                          " (the device has " + std::to_string(properties.limits.maxPushConstantsSize) + ")");
    if (properties.limits.maxImageDimension2D < 1025)
        missing.push_back("maxImageDimension2D >= 1025 (the device has " +
                          std::to_string(properties.limits.maxImageDimension2D) + ")");
    return missing;
}

std::unique_ptr<Context> Context::adopt(VkInstance instance, VkPhysicalDevice physicalDevice, VkDevice device,
                                        VkQueue queue, uint32_t family, const VkDeviceCreateInfo& enabled)
{
    std::unique_ptr<Context> c(new Context());
    vkGetPhysicalDeviceProperties(physicalDevice, &c->properties);
    uint32_t familyCount = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(physicalDevice, &familyCount, nullptr);
    std::vector<VkQueueFamilyProperties> families(familyCount);
    vkGetPhysicalDeviceQueueFamilyProperties(physicalDevice, &familyCount, families.data());
    if (family >= familyCount)
        throw Error("Context::adopt: queue family " + std::to_string(family) + " does not exist (the device has " +
                    std::to_string(familyCount) + ")");
    const auto missing = missingDeviceRequirements(c->properties, families[family].queueFlags, enabled);
    if (!missing.empty()) {
        std::string list;
        for (const auto& m : missing) list += (list.empty() ? "" : "; ") + m;
        throw Error("Context::adopt: the device '" + std::string(c->properties.deviceName) +
                    "' lacks what ngi needs: " + list);
    }
    const VkPhysicalDeviceFeatures features = enabledCoreFeatures(enabled);
    c->pipelineStatistics = features.pipelineStatisticsQuery;
    c->independentBlend = features.independentBlend;
    c->drawIndirectFirstInstance = features.drawIndirectFirstInstance;
    c->instance = instance;
    c->physicalDevice = physicalDevice;
    c->device = device;
    c->queue = queue;
    c->queueFamily = family;
    vkGetPhysicalDeviceMemoryProperties(physicalDevice, &c->memoryProperties);
    VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    poolInfo.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT | VK_COMMAND_POOL_CREATE_TRANSIENT_BIT;
    poolInfo.queueFamilyIndex = family;
    NGI_VK_CHECK(vkCreateCommandPool(device, &poolInfo, nullptr, &c->commandPool_));
    return c;
}

Context::~Context()
{
    if (device) {
        vkDeviceWaitIdle(device);
        if (commandPool_) vkDestroyCommandPool(device, commandPool_, nullptr);
    }
    if (!owns_) return;
    if (device) vkDestroyDevice(device, nullptr);
    if (messenger_) {
        auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"));
        if (destroy) destroy(instance, messenger_, nullptr);
    }
    if (instance) vkDestroyInstance(instance, nullptr);
}

std::vector<std::string> Context::validationMessages() const
{
    std::lock_guard lock(messagesMutex_);
    return messages_;
}

namespace {

// The one-shot command buffer of submitAndWait, freed on every path (exceptions included).
struct OneShotCommandBuffer {
    VkDevice device;
    VkCommandPool pool;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    OneShotCommandBuffer(VkDevice d, VkCommandPool p) : device(d), pool(p)
    {
        VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
        alloc.commandPool = pool;
        alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        alloc.commandBufferCount = 1;
        NGI_VK_CHECK(vkAllocateCommandBuffers(device, &alloc, &cmd));
    }
    ~OneShotCommandBuffer() { vkFreeCommandBuffers(device, pool, 1, &cmd); }
    OneShotCommandBuffer(const OneShotCommandBuffer&) = delete;
    OneShotCommandBuffer& operator=(const OneShotCommandBuffer&) = delete;
};

}  // namespace

void Context::submitAndWait(const std::function<void(VkCommandBuffer)>& record) const
{
    const OneShotCommandBuffer buffer(device, commandPool_);
    const VkCommandBuffer cmd = buffer.cmd;
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    NGI_VK_CHECK(vkBeginCommandBuffer(cmd, &begin));
    record(cmd);
    NGI_VK_CHECK(vkEndCommandBuffer(cmd));
    UniqueFence fence(device);
    VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    NGI_VK_CHECK(vkCreateFence(device, &fenceInfo, nullptr, fence.out()));
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cmd;
    NGI_VK_CHECK(vkQueueSubmit(queue, 1, &submit, fence.get()));
    const VkFence fences[] = {fence.get()};
    NGI_VK_CHECK(vkWaitForFences(device, 1, fences, VK_TRUE, UINT64_MAX));
}

uint32_t Context::memoryType(uint32_t typeBits, VkMemoryPropertyFlags required) const
{
    for (uint32_t i = 0; i < memoryProperties.memoryTypeCount; ++i)
        if ((typeBits & (1u << i)) && (memoryProperties.memoryTypes[i].propertyFlags & required) == required) return i;
    throw Error("no Vulkan memory type with the required properties");
}

}  // namespace ngi::vk
