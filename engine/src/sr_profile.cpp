// ngi engine: GPU timestamps per super-resolution op (SuperResolutionOptions::profile).
#include "sr_internal.h"

#include "ngi/engine/super_resolution.h"
#include "sr_kernels.h"
#include "ngi/engine/vk_check.h"
#include "ngi/error.h"
#include <algorithm>
#include <cmath>
#include <cstring>

namespace ngi::vk {

void SuperResolution::beginTimestamps(VkCommandBuffer cmd)
{
    profiledOps_.clear();
    if (!queries_) return;
    vkCmdResetQueryPool(cmd, queries_, 0, queryCount_);
    vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, queries_, 0);
}

void SuperResolution::markTimestamp(VkCommandBuffer cmd, std::string name, std::string kind, uint64_t multiplyAdds)
{
    if (!queries_) return;
    profiledOps_.push_back({std::move(name), std::move(kind), 0.0, multiplyAdds});
    vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_, uint32_t(profiledOps_.size()));
}

std::vector<SrOpTiming> SuperResolution::profile() const
{
    if (!queries_ || profiledOps_.empty()) return {};
    std::vector<uint64_t> ticks(profiledOps_.size() + 1);
    NGI_VK_CHECK(vkGetQueryPoolResults(context_.device, queries_, 0, uint32_t(ticks.size()), ticks.size() * 8,
                                       ticks.data(), 8, VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
    std::vector<SrOpTiming> ops = profiledOps_;
    const double period = context_.properties.limits.timestampPeriod;
    for (size_t i = 0; i < ops.size(); ++i) ops[i].milliseconds = double(ticks[i + 1] - ticks[i]) * period * 1e-6;
    return ops;
}

}  // namespace ngi::vk
