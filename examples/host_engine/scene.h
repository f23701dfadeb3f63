// ngi-host-demo: the host's scene (ngi instances on a grid, its props, the sun, the moving
// camera) and the pixel checks of its last frame.
#pragma once

#include "ngi/engine/lod.h"

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace host {

struct Instance {
    size_t asset;
    glm::vec3 base;    // world-space point on the ground under its centre
    glm::vec3 centre;  // world-space centre of its bounds
    glm::mat4 world;   // object -> world
};

struct Prop {
    glm::vec3 centre, halfExtent;
    glm::vec4 colour;
};

struct Camera {
    glm::vec3 eye;
    glm::mat4 viewProjection;  // reverse-Z: depth 1 at the near plane, 0 at the far one
};

struct Scene {
    std::vector<Instance> instances;
    std::vector<Prop> props;  // props[0]: in front of `hiddenInstance`; props[1]: behind `frontInstance`
    size_t hiddenInstance = 0, frontInstance = 0;
    float groundHalfSize = 12.0f;
    glm::vec3 toLight{0.0f}, lightEye{0.0f};
    glm::mat4 lightViewProjection{1.0f};
    uint32_t frames = 1;

    size_t countOf(size_t asset) const
    {
        return size_t(
            std::count_if(instances.begin(), instances.end(), [&](const Instance& i) { return i.asset == asset; }));
    }

    // An orbit over 50 degrees of azimuth around the grid, outside it, looking at its middle.
    Camera camera(uint32_t frame, float aspect) const
    {
        const float t = frames > 1 ? float(frame) / float(frames - 1) : 1.0f;
        const float a = glm::radians(200.0f + 50.0f * t);
        Camera c;
        c.eye = glm::vec3(11.5f * std::cos(a), 3.2f, 11.5f * std::sin(a));
        glm::mat4 proj =
            glm::perspectiveRH_ZO(glm::radians(42.0f), aspect, 200.0f, 0.1f);  // near/far swapped: reverse-Z
        proj[1][1] *= -1.0f;
        c.viewProjection = proj * glm::lookAtRH(c.eye, glm::vec3(0.0f, 0.3f, 0.0f), glm::vec3(0, 1, 0));
        return c;
    }
};

// 12 x 10 instances (alternating assets, each fitted to a box of about one unit, turned about
// the vertical), pillars between them, and the two props the checks need, placed from the
// last frame's camera: one between it and the nearest instance, one behind another.
inline Scene makeScene(const std::vector<ngi::AssetLodMetrics>& metrics, uint32_t frames)
{
    Scene s;
    s.frames = frames;
    const glm::vec4 terracotta(0.78f, 0.36f, 0.20f, 1.0f);
    for (int row = 0; row < 10; ++row)
        for (int col = 0; col < 12; ++col) {
            Instance i;
            i.asset = size_t((row + col) % 2);
            const ngi::AssetLodMetrics& m = metrics[i.asset];
            const glm::vec3 extent = m.boundsMax - m.boundsMin;
            const float size = 0.85f + 0.1f * float((row * 7 + col * 3) % 4);
            const float scale = size / std::max({extent.x, extent.y, extent.z});
            const float turn = glm::radians(37.0f * float(row * 12 + col));
            i.base = glm::vec3(1.4f * (float(col) - 5.5f), 0.0f, 1.4f * (float(row) - 4.5f));
            i.centre = i.base + glm::vec3(0.0f, 0.5f * scale * extent.y, 0.0f);
            i.world = glm::translate(glm::mat4(1.0f), i.centre) *
                glm::rotate(glm::mat4(1.0f), turn, glm::vec3(0, 1, 0)) * glm::scale(glm::mat4(1.0f), glm::vec3(scale)) *
                glm::translate(glm::mat4(1.0f), -0.5f * (m.boundsMin + m.boundsMax));
            s.instances.push_back(i);
        }
    const glm::vec3 eye = s.camera(frames - 1, 1.0f).eye;
    std::vector<size_t> order(s.instances.size());
    for (size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
        return glm::distance(s.instances[a].centre, eye) < glm::distance(s.instances[b].centre, eye);
    });
    s.hiddenInstance = order[0];
    for (size_t k : order)  // the nearest instance of the baked asset (closed: its centre is on it) away from the first
        if (s.instances[k].asset == 0 && glm::distance(s.instances[k].base, s.instances[order[0]].base) > 2.5f) {
            s.frontInstance = k;
            break;
        }
    // A pillar a third of the way from the hidden instance towards the camera (on the ground).
    const Instance& hidden = s.instances[s.hiddenInstance];
    glm::vec3 towards = glm::vec3(eye.x, 0.0f, eye.z) - hidden.base;
    const glm::vec3 p = hidden.base + towards * (1.4f / glm::length(towards));
    s.props.push_back({p + glm::vec3(0.0f, 1.0f, 0.0f), glm::vec3(0.22f, 1.0f, 0.22f), terracotta});
    // A block behind the front instance, seen past it.
    const Instance& front = s.instances[s.frontInstance];
    towards = glm::normalize(glm::vec3(eye.x, 0.0f, eye.z) - front.base);
    s.props.push_back(
        {front.base - towards * 0.75f + glm::vec3(0.0f, 0.75f, 0.0f), glm::vec3(0.3f, 0.75f, 0.3f), terracotta});
    // Pillars between the instances.
    for (int k = 0; k < 8; ++k) {
        const glm::vec3 c(1.4f * (float(1 + (k * 5) % 11) - 5.0f), 0.0f, 1.4f * (float(1 + (k * 3) % 9) - 4.0f));
        s.props.push_back({c + glm::vec3(0.0f, 0.9f, 0.0f), glm::vec3(0.15f, 0.9f, 0.15f), terracotta});
    }

    s.toLight = glm::normalize(glm::vec3(0.62f, 0.72f, 0.30f));  // a low sun: long shadows
    s.lightEye = s.toLight * 30.0f;
    s.lightViewProjection = glm::orthoRH_ZO(-13.0f, 13.0f, -13.0f, 13.0f, 1.0f, 60.0f) *
        glm::lookAtRH(s.lightEye, glm::vec3(0.0f), glm::vec3(0, 1, 0));
    return s;
}

// Does the ray from `from` towards `to` hit the box before reaching `to`?
inline bool rayHitsBoxBefore(glm::vec3 from, glm::vec3 to, const Prop& box)
{
    const glm::vec3 d = to - from;
    float t0 = 0.0f, t1 = 1.0f;
    for (int a = 0; a < 3; ++a) {
        const float lo = box.centre[a] - box.halfExtent[a], hi = box.centre[a] + box.halfExtent[a];
        if (std::abs(d[a]) < 1e-9f) {
            if (from[a] < lo || from[a] > hi) return false;
            continue;
        }
        float ta = (lo - from[a]) / d[a], tb = (hi - from[a]) / d[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    return t0 <= t1;
}

// The last frame's pixels: the ground darker where the props' shadows fall (the shadow
// pass drew them), the pillar in front of the hidden instance drawn over it (host geometry
// occludes ngi's, reverse-Z), and the front instance drawn over the block behind it (ngi's
// occludes the host's). Returns the number of failed checks (printed).
inline int checkFrame(const Scene& s, const glm::mat4& viewProjection, const std::vector<uint8_t>& rgba, uint32_t width,
                      uint32_t height)
{
    int failures = 0;
    auto expect = [&](bool ok, const std::string& what) {
        std::printf("check: %s: %s\n", what.c_str(), ok ? "ok" : "FAILED");
        failures += !ok;
    };
    auto pixel = [&](glm::vec3 p, int* x, int* y) {
        const glm::vec4 c = viewProjection * glm::vec4(p, 1.0f);
        *x = int((c.x / c.w * 0.5f + 0.5f) * float(width));
        *y = int((c.y / c.w * 0.5f + 0.5f) * float(height));
        return c.w > 0.0f && *x >= 0 && *y >= 0 && *x < int(width) && *y < int(height);
    };
    auto at = [&](int x, int y) { return &rgba[(size_t(y) * width + size_t(x)) * 4]; };
    auto isGround = [](const uint8_t* p) { return p[1] > 20 && p[1] > 1.3f * p[0] && p[1] > 1.2f * p[2]; };
    auto isProp = [](const uint8_t* p) { return p[0] > 20 && p[0] > 1.5f * p[1] && p[0] > 1.8f * p[2]; };
    auto isNgi = [](const uint8_t* p) {
        const int hi = std::max({p[0], p[1], p[2]}), lo = std::min({p[0], p[1], p[2]});
        return hi > 25 && hi - lo < hi / 4;
    };
    auto luminance = [](const uint8_t* p) { return 0.2126f * p[0] + 0.7152f * p[1] + 0.0722f * p[2]; };
    size_t ngi = 0, ground = 0, props = 0;
    std::vector<float> groundLuminance;
    for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x) {
            const uint8_t* p = at(int(x), int(y));
            ngi += isNgi(p);
            props += isProp(p);
            if (isGround(p)) {
                ++ground;
                groundLuminance.push_back(luminance(p));
            }
        }
    const size_t all = size_t(width) * height;
    std::printf("check: pixels: ngi %zu, ground %zu, props %zu of %zu\n", ngi, ground, props, all);
    expect(ngi > all / 20 && ground > all / 10 && props > all / 200,
           "ngi instances, ground and props all cover the frame");
    if (groundLuminance.empty()) return failures + 1;
    std::nth_element(groundLuminance.begin(), groundLuminance.begin() + groundLuminance.size() / 2,
                     groundLuminance.end());
    const float litGround = groundLuminance[groundLuminance.size() / 2];  // most of the ground is in the sun

    // Shadows: the ground points the sun sees through each prop's axis at 25%..90% of its
    // height (where no ngi instance stands in front of them on screen).
    int shadowsSeen = 0, shadowsDark = 0;
    for (size_t k = 0; k < s.props.size(); ++k) {
        const Prop& pillar = s.props[k];
        for (float f = 0.25f; f < 0.95f; f += 0.1625f) {
            const glm::vec3 q = glm::vec3(pillar.centre.x, 2.0f * f * pillar.halfExtent.y, pillar.centre.z);
            const glm::vec3 onGround = q - s.toLight * (q.y / s.toLight.y);
            int x, y;
            if (!pixel(onGround, &x, &y) || !isGround(at(x, y))) continue;  // off screen or behind something
            ++shadowsSeen;
            shadowsDark += luminance(at(x, y)) < 0.6f * litGround;
        }
    }
    expect(shadowsSeen >= 3 && shadowsDark == shadowsSeen,
           std::to_string(shadowsDark) + " of " + std::to_string(shadowsSeen) +
               " visible points of the props' shadows darker than 0.6 x the lit ground (" +
               std::to_string(int(litGround)) + ")");

    // Occlusion, both ways, where the geometry says so (a ray test on the CPU).
    const glm::vec3 eye = s.camera(s.frames - 1, float(width) / float(height)).eye;
    const Instance& hidden = s.instances[s.hiddenInstance];
    int x, y;
    expect(rayHitsBoxBefore(eye, hidden.centre, s.props[0]) && pixel(hidden.centre, &x, &y) && isProp(at(x, y)),
           "the host's pillar hides the ngi instance behind it");
    const Instance& front = s.instances[s.frontInstance];
    const glm::vec3 beyond = eye + (front.centre - eye) * 1.6f;
    expect(rayHitsBoxBefore(front.centre, beyond, s.props[1]) && pixel(front.centre, &x, &y) && isNgi(at(x, y)),
           "the ngi instance hides the host's block behind it");
    const Prop& block = s.props[1];
    expect(pixel(block.centre + glm::vec3(0.0f, 0.8f * block.halfExtent.y, 0.0f), &x, &y) && isProp(at(x, y)),
           "the block shows above the instance");
    return failures;
}

}  // namespace host
