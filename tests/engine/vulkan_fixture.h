// Test fixture: a Vulkan context on the default device (lavapipe in CI) with the validation
// layer on. Any validation warning or error fails the test that produced it.
#pragma once

#include "ngi/engine/context.h"
#include "ngi/engine/renderer.h"

#include <gtest/gtest.h>

#include <memory>

class VulkanTest : public ::testing::Test {
protected:
    static void SetUpTestSuite()
    {
        context_ = ngi::vk::Context::create({.validation = true});
        renderer_ = std::make_unique<ngi::vk::Renderer>(*context_);
    }
    static void TearDownTestSuite()
    {
        renderer_.reset();
        context_.reset();
    }
    void SetUp() override { messagesBefore_ = context_->validationMessages().size(); }
    void TearDown() override
    {
        const auto messages = context_->validationMessages();
        for (size_t i = messagesBefore_; i < messages.size(); ++i) ADD_FAILURE() << messages[i];
    }
    const ngi::vk::Context& context() const { return *context_; }
    const ngi::vk::Renderer& renderer() const { return *renderer_; }

private:
    static inline std::unique_ptr<ngi::vk::Context> context_;
    static inline std::unique_ptr<ngi::vk::Renderer> renderer_;
    size_t messagesBefore_ = 0;
};
