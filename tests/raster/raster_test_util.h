// tests/raster/raster_test_util.h — scenes built in code for the rasterizer tests.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "core/hash.h"
#include "raster/raster.h"
#include "scenes/scene.h"

namespace aq::test {

//! Settings for exact geometric tests: no tremor, no bleeding displacement, one sample per pixel
//! (no coverage antialiasing: antialias_test.cpp tests it), one thread unless told.
inline raster::RenderSettings plain_settings(int w, int h) {
    raster::RenderSettings s;
    s.width = w;
    s.height = h;
    s.tremor.enabled = false;
    s.bleed_displacement = false;
    s.antialias = raster::RenderSettings::Antialias::None;
    return s;
}

//! Orthographic camera mapping world (x, y) to pixel (x + W/2, H/2 - y); looks down -Z.
inline scene::Camera pixel_camera(int w, int h) {
    scene::Camera c;
    c.orthographic = true;
    c.xmag = 0.5f * float(w);
    c.ymag = 0.5f * float(h);
    c.znear = 0.1f;
    c.zfar = 100.0f;
    return c;
}

//! World position of a pixel-space point for pixel_camera.
inline glm::vec3 px(int w, int h, float x, float y, float z = -1.0f) {
    return {x - 0.5f * float(w), 0.5f * float(h) - y, z};
}

inline scene::Primitive make_prim(std::vector<glm::vec3> pos, std::vector<std::uint32_t> idx) {
    scene::Primitive p;
    p.normals.assign(pos.size(), glm::vec3(0, 0, 1));
    p.positions = std::move(pos);
    p.indices = std::move(idx);
    return p;
}

//! A scene with one material and one instance per primitive (object ids 1, 2, ...).
inline scene::Scene scene_of(std::vector<scene::Primitive> prims, scene::Material mat = {}) {
    scene::Scene s;
    s.materials.push_back(mat);
    for (std::size_t i = 0; i < prims.size(); ++i) {
        scene::Mesh m;
        m.primitives.push_back(std::move(prims[i]));
        s.meshes.push_back(std::move(m));
        scene::Instance inst;
        inst.mesh = int(i);
        inst.object_id = std::uint32_t(i + 1);
        s.instances.push_back(inst);
    }
    return s;
}

//! Material whose colour output equals its base colour: no dilution, no cangiante, DF = 1.
inline scene::Material flat_material(glm::vec4 base = glm::vec4(1.0f)) {
    scene::Material m;
    m.base_color = base;
    m.wc.dilute = 0;
    m.wc.cangiante = 0;
    m.wc.diffuse_factor = 0;
    m.wc.specular = 0;
    return m;
}

//! UV sphere (closed, outward normals, CCW outside).
inline scene::Primitive uv_sphere(int slices, int stacks, float r) {
    scene::Primitive p;
    for (int j = 0; j <= stacks; ++j) {
        const float th = float(M_PI) * float(j) / float(stacks);
        for (int i = 0; i <= slices; ++i) {
            const float ph = 2.0f * float(M_PI) * float(i) / float(slices);
            glm::vec3 n(std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph));
            if (j == 0 || j == stacks) n = glm::vec3(0, j == 0 ? 1 : -1, 0);
            p.positions.push_back(n * r);
            p.normals.push_back(n);
        }
    }
    // Weld the seam and the poles so the mesh is closed by index (shared vertices).
    auto id = [&](int i, int j) -> std::uint32_t {
        if (j == 0) return 0;
        if (j == stacks) return std::uint32_t(stacks * (slices + 1));
        return std::uint32_t(j * (slices + 1) + (i % slices));
    };
    for (int j = 0; j < stacks; ++j)
        for (int i = 0; i < slices; ++i) {
            const std::uint32_t a = id(i, j), b = id(i + 1, j), c = id(i, j + 1), d = id(i + 1, j + 1);
            if (j != 0) p.indices.insert(p.indices.end(), {a, b, c});
            if (j != stacks - 1) p.indices.insert(p.indices.end(), {b, d, c});
        }
    return p;
}

//! Camera at `eye` looking at `at` (up +Y), perspective.
inline scene::Camera look_at(glm::vec3 eye, glm::vec3 at, float yfov = 0.8f, float zn = 0.1f,
                             float zf = 100.0f) {
    scene::Camera c;
    c.view = glm::lookAt(eye, at, glm::vec3(0, 1, 0));
    c.yfov = yfov;
    c.znear = zn;
    c.zfar = zf;
    return c;
}

//! Camera framing the world bounds of a scene from +Z (the CLI does something similar).
inline scene::Camera frame_scene(const scene::Scene& s, float yfov = 0.7f) {
    const scene::Bounds b = s.world_bounds();
    const glm::vec3 c = 0.5f * (b.min + b.max);
    const float r = 0.5f * glm::length(b.max - b.min);
    const float d = r / std::sin(0.5f * yfov) * 1.05f;
    return look_at(c + glm::normalize(glm::vec3(0.35f, 0.3f, 1.0f)) * d, c, yfov, d * 0.05f, d * 3.0f);
}

inline std::vector<std::pair<std::string, std::string>> hashes(const Targets& t) {
    std::vector<std::pair<std::string, std::string>> out;
    for (const auto& [name, img] : t.all()) out.emplace_back(name, sha256_hex(img));
    return out;
}

}  // namespace aq::test
