// ngi engine: the charts' base colour images on the GPU (color_images.h).
#include "ngi/engine/color_images.h"

#include "ngi/engine/vk_check.h"
#include "ngi/error.h"
#include "ngi/srgb.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

namespace ngi::vk {

std::vector<std::vector<uint8_t>> colorMipChain(const std::vector<uint8_t>& rgba, uint32_t n)
{
    std::vector<std::vector<uint8_t>> chain{rgba};
    const std::array<float, 256>& linear = srgb8ToLinear();
    for (uint32_t size = n; size > 1;) {
        const uint32_t next = std::max(1u, size / 2);
        const std::vector<uint8_t>& fine = chain.back();
        std::vector<uint8_t> coarse(size_t(next) * next * 4);
        for (uint32_t y = 0; y < next; ++y)
            for (uint32_t x = 0; x < next; ++x) {
                // The box of 2 x 2 texels; an odd size's last row / column joins the last box.
                const uint32_t x0 = 2 * x, y0 = 2 * y;
                const uint32_t x1 = x + 1 == next ? size - 1 : 2 * x + 1, y1 = y + 1 == next ? size - 1 : 2 * y + 1;
                double sum[4] = {0, 0, 0, 0};
                uint32_t count = 0;
                for (uint32_t yy = y0; yy <= y1; ++yy)
                    for (uint32_t xx = x0; xx <= x1; ++xx, ++count) {
                        const uint8_t* t = &fine[(size_t(yy) * size + xx) * 4];
                        for (int k = 0; k < 3; ++k) sum[k] += linear[t[k]];
                        sum[3] += t[3] / 255.0;
                    }
                uint8_t* out = &coarse[(size_t(y) * next + x) * 4];
                for (int k = 0; k < 3; ++k) out[k] = uint8_t(std::lround(255.0 * linearToSrgb(sum[k] / count)));
                out[3] = uint8_t(std::lround(255.0 * sum[3] / count));
            }
        chain.push_back(std::move(coarse));
        size = next;
    }
    return chain;
}

ChartColorImages::ChartColorImages(const Context& context, const Asset& asset) : sampler_(context.device)
{
    const VkDevice device = context.device;
    VkSamplerCreateInfo info{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    info.magFilter = info.minFilter = VK_FILTER_LINEAR;
    info.mipmapMode = VK_SAMPLER_MIPMAP_MODE_LINEAR;
    info.addressModeU = info.addressModeV = info.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    info.maxLod = VK_LOD_CLAMP_NONE;
    NGI_VK_CHECK(vkCreateSampler(device, &info, nullptr, sampler_.out()));

    // The 1 x 1 stand-in for charts without colour (ngi's shading then uses its own grey, a
    // host's material sees this grey), then each coloured chart.
    struct Upload {
        std::vector<std::vector<uint8_t>> levels;
        uint32_t size;
    };
    std::vector<Upload> uploads;
    uploads.push_back({{{199, 204, 214, 255}}, 1});
    imageOfChart_.assign(asset.charts.size(), 0);
    cutsOut_.assign(asset.charts.size(), false);
    for (size_t c = 0; c < asset.charts.size(); ++c) {
        const AssetChart& chart = asset.charts[c];
        if (chart.baseColor.empty()) continue;
        const uint32_t n = chart.baseColorSize();
        if (chart.baseColor.size() != size_t(n) * n * 4)
            throw Error("chart " + std::to_string(c) + ": its base colour has " +
                        std::to_string(chart.baseColor.size()) + " bytes, not " + std::to_string(size_t(n) * n * 4));
        for (size_t i = 3; i < chart.baseColor.size() && !cutsOut_[c]; i += 4) cutsOut_[c] = chart.baseColor[i] < 255;
        imageOfChart_[c] = uploads.size();
        uploads.push_back({colorMipChain(chart.baseColor, n), n});
        any_ = true;
    }
    VkDeviceSize staged = 0;
    for (const Upload& u : uploads)
        for (const std::vector<uint8_t>& level : u.levels) staged += level.size();
    UniqueBuffer staging(context,
                         createBuffer(context, staged, VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                      VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT));
    VkDeviceSize offset = 0;
    std::vector<std::vector<VkBufferImageCopy>> copies;
    for (const Upload& u : uploads) {
        images_.emplace_back(context,
                             createImage(context, u.size, u.size, VK_FORMAT_R8G8B8A8_SRGB,
                                         VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
                                         VK_IMAGE_ASPECT_COLOR_BIT, VK_SAMPLE_COUNT_1_BIT, uint32_t(u.levels.size())));
        std::vector<VkBufferImageCopy>& regions = copies.emplace_back();
        for (uint32_t l = 0; l < u.levels.size(); ++l) {
            const uint32_t side = std::max(1u, u.size >> l);
            std::memcpy(static_cast<uint8_t*>(staging->mapped) + offset, u.levels[l].data(), u.levels[l].size());
            VkBufferImageCopy region{};
            region.bufferOffset = offset;
            region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, l, 0, 1};
            region.imageExtent = {side, side, 1};
            regions.push_back(region);
            offset += u.levels[l].size();
        }
    }
    context.submitAndWait([&](VkCommandBuffer cmd) {
        for (size_t i = 0; i < images_.size(); ++i) {
            const uint32_t levels = uint32_t(uploads[i].levels.size());
            VkImageMemoryBarrier barrier{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
            barrier.srcQueueFamilyIndex = barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
            barrier.image = images_[i]->image;
            barrier.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, levels, 0, 1};
            barrier.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
            barrier.newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
            barrier.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
            vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, nullptr,
                                 0, nullptr, 1, &barrier);
            vkCmdCopyBufferToImage(cmd, staging->buffer, images_[i]->image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                                   uint32_t(copies[i].size()), copies[i].data());
            barrier.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
            barrier.newLayout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
            barrier.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
            barrier.dstAccessMask = VK_ACCESS_SHADER_READ_BIT;
            vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT, 0, 0,
                                 nullptr, 0, nullptr, 1, &barrier);
        }
    });
}

bool ChartColorImages::cutsOut() const
{
    for (bool c : cutsOut_)
        if (c) return true;
    return false;
}

VkImageView ChartColorImages::view(size_t chart) const { return images_.at(imageOfChart_.at(chart))->view; }

VkDeviceSize ChartColorImages::bytes() const
{
    VkDeviceSize total = 0;
    for (const UniqueImage& image : images_) total += image->bytes;
    return total;
}

}  // namespace ngi::vk
