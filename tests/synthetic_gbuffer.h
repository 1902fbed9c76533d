// tests/synthetic_gbuffer.h — the one synthetic G-buffer generator, for the unit tests, the
// benchmarks (bench/) and the GPU-equivalent reference checks (tests/reference/, bench/reference_bench):
// every target of the rasterizer's layout (core/targets.h kGBufferLayout) with render-like content,
// and an input image for any other port a stage declares (intermediates), so registry-wide tests
// also cover stages added later. Deterministic in (size, seed); no thread or clock is consulted.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include <glm/glm.hpp>

#include "core/hash.h"
#include "core/image.h"
#include "core/targets.h"

namespace aq::test {

namespace synthetic_detail {
//! Value noise in [0, 1) keyed by two integers and the seed (core/hash.h lowbias32).
inline float hash01(std::uint32_t a, std::uint32_t b, std::uint32_t seed) {
    return float(hash32(a * 0x9E3779B1U ^ hash32(b + 0x85EBCA77U * seed))) * (1.0f / 4294967296.0f);
}
struct Disk {
    float cx, cy, r, z;
};
}  // namespace synthetic_detail

//! Every G-buffer target of spec §1 at w x h: `color` (smooth gradients, hard object edges,
//! coverage in alpha, background alpha 0), the four `ctrl.*` targets (painted patches, soft and
//! hard, values over the whole signed range [-1, 1]), `depth.linear` (slanted planes, steps, +inf
//! background), `normal` (view space, spheres and planes), `object_id`, `diffuse`, `specular`.
inline Targets synthetic_gbuffer(int w, int h, std::uint32_t seed = 1) {
    using synthetic_detail::Disk;
    using synthetic_detail::hash01;
    Targets t;
    // Every target of the rasterizer's layout (core/targets.h kGBufferLayout), with its channels.
    for (const target::GBufferTarget& g : target::kGBufferLayout) t.create(g.name, w, h, g.channels);
    ImageF& color = t.get_mut(target::kColor);
    ImageF& depth = t.get_mut(target::kDepthLinear);
    ImageF& normal = t.get_mut(target::kNormal);
    ImageF& oid = t.get_mut(target::kObjectId);
    ImageF& diffuse = t.get_mut(target::kDiffuse);
    ImageF& specular = t.get_mut(target::kSpecular);
    ImageF* ctrl[control::kNumTargets];
    for (int k = 0; k < control::kNumTargets; ++k) ctrl[k] = &t.get_mut(control::kTargets[k]);
    const float inf = std::numeric_limits<float>::infinity();
    const float m = float(std::min(w, h));
    // Three overlapping spheres (disks with sphere normals and curved depth) in front of a slanted
    // ground plane that covers the lower part; the rest is background.
    const Disk disks[3] = {{0.33f * w, 0.42f * h, 0.26f * m, 14.0f},
                           {0.62f * w, 0.52f * h, 0.22f * m, 11.0f},
                           {0.78f * w, 0.30f * h, 0.14f * m, 30.0f}};
    const glm::vec3 base[3] = {{0.76f, 0.37f, 0.0f}, {0.15f, 0.45f, 0.85f}, {0.95f, 0.9f, 0.2f}};
    const glm::vec3 light = glm::normalize(glm::vec3(-0.4f, 0.6f, 0.7f));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float px = x + 0.5f, py = y + 0.5f;
            float z = inf, a = 0.0f;
            glm::vec3 n(0.0f, 0.0f, 1.0f), c(0.0f);
            float id = 0.0f;
            // ground plane: lower 35 %, depth growing upwards (a slanted plane), checker edges
            if (py > 0.65f * h) {
                z = 9.0f + 40.0f * (1.0f - py / h);
                n = glm::normalize(glm::vec3(0.0f, 0.8f, 0.6f));
                const bool check = ((x / 12) + (y / 12)) % 2 == 0;
                c = check ? glm::vec3(0.55f, 0.62f, 0.4f) : glm::vec3(0.35f, 0.42f, 0.25f);
                c += 0.15f * glm::vec3(px / w);
                a = 1.0f;
                id = 4.0f;
            }
            for (int k = 0; k < 3; ++k) {
                const float dx = (px - disks[k].cx) / disks[k].r, dy = (py - disks[k].cy) / disks[k].r;
                const float r2 = dx * dx + dy * dy;
                if (r2 >= 1.0f) continue;
                const float nz = std::sqrt(1.0f - r2);
                const float zk = disks[k].z - 3.0f * nz;
                if (zk >= z) continue;
                z = zk;
                n = glm::vec3(dx, -dy, nz);
                const float lam = std::max(0.0f, glm::dot(n, light));
                c = base[k] * (0.35f + 0.65f * lam) + glm::vec3(0.08f * (1.0f - nz));
                a = r2 > 0.92f ? 1.0f - (r2 - 0.92f) / 0.08f * 0.6f : 1.0f;  // soft coverage at rims
                id = float(k + 1);
            }
            c = glm::clamp(c, 0.0f, 1.0f);
            color.at(x, y, 0) = c.r, color.at(x, y, 1) = c.g, color.at(x, y, 2) = c.b, color.at(x, y, 3) = a;
            depth.at(x, y, 0) = z;
            normal.at(x, y, 0) = n.x, normal.at(x, y, 1) = n.y, normal.at(x, y, 2) = n.z;
            oid.at(x, y, 0) = id;
            diffuse.at(x, y, 0) = std::max(0.0f, glm::dot(n, light));
            specular.at(x, y, 0) = std::pow(std::max(0.0f, n.z), 16.0f) * (a > 0 ? 1.0f : 0.0f);
            // Control targets: soft painted blobs (sin patterns) over the whole signed range, a few
            // hard-edged patches at full +-1, and small per-pixel noise. Zero on the background.
            for (int k = 0; k < 4; ++k)
                for (int ch = 0; ch < 4; ++ch) {
                    const float u = px / w, v = py / h;
                    float val = std::sin(6.2831853f * (u * (1.3f + 0.4f * ch) + v * (0.7f + 0.3f * k)) + float(k * 4 + ch));
                    val *= 0.9f;
                    const int cx = int(u * 5.0f), cy = int(v * 4.0f);
                    const float patch = hash01(std::uint32_t(cx + 16 * k), std::uint32_t(cy + 16 * ch), seed);
                    if (patch < 0.18f) val = 1.0f;
                    else if (patch > 0.86f) val = -1.0f;
                    else if (patch > 0.78f) val = 0.0f;
                    val += 0.05f * (hash01(std::uint32_t(x), std::uint32_t(y * 16 + k * 4 + ch), seed) - 0.5f);
                    val = std::clamp(val, -1.0f, 1.0f);
                    ctrl[k]->at(x, y, ch) = a > 0.0f ? val : 0.0f;
                }
        }
    return t;
}

//! A smooth-plus-edges pattern in [0, 1] with `channels` channels, for inputs nothing in the
//! G-buffer provides (intermediates such as `edges`, `bleed`, `paper`).
inline ImageF synthetic_pattern(int w, int h, int channels, std::uint32_t seed) {
    ImageF img(w, h, channels);
    const float s = float(seed % 7) + 1.0f;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float u = (x + 0.5f) / w, v = (y + 0.5f) / h;
            const bool inside = std::abs(u - 0.5f) < 0.3f && std::abs(v - 0.45f) < 0.25f;
            for (int c = 0; c < channels; ++c) {
                float val = 0.5f + 0.5f * std::sin(6.2831853f * (u * (c + 1) + v * s * 0.5f) + c);
                if (inside) val = 0.25f * val + (c % 2 ? 0.7f : 0.1f);
                img.at(x, y, c) = std::clamp(val, 0.0f, 1.0f);
            }
        }
    return img;
}

//! The input image of a port: the G-buffer target of that name when `channels` matches its layout
//! (from synthetic_gbuffer, so every caller sees the same G-buffer content), else
//! synthetic_pattern.
//! ID maps (LD06 layer or object IDs: names ending in "_id", one channel) get integer IDs 0..9 in
//! blocks (0 = background), so every layer of an ID split is exercised.
inline ImageF synthetic_target(const std::string& name, int channels, int w, int h, std::uint32_t seed = 1) {
    if (target::gbuffer_channels(name.c_str()) == channels) return synthetic_gbuffer(w, h, seed).get(name);
    if (channels == 1 && name.size() > 3 && name.compare(name.size() - 3, 3, "_id") == 0) {
        ImageF img(w, h, 1);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                img.at(x, y, 0) = float(hash32(std::uint32_t(x / 7) * 131u + std::uint32_t(y / 5) + seed) % 10u);
        return img;
    }
    return synthetic_pattern(w, h, channels, seed);
}

}  // namespace aq::test
