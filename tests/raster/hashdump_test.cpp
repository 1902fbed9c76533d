// tests/raster/hashdump_test.cpp — perf-work aid: with AQ_RASTER_HASHDUMP=1, renders the 871k
// dragon (bench camera, default settings) at 1920x1080 with 1 and 2 threads and prints the SHA-256
// of every target, so optimisations can be checked bit-for-bit. Skipped otherwise.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>

#include "core/hash.h"
#include "raster/raster.h"
#include "scenes/gltf_loader.h"

namespace {
aq::scene::Camera bench_camera(const aq::scene::Scene& s, float aspect) {
    const aq::scene::Bounds b = s.world_bounds();
    const glm::vec3 c = 0.5f * (b.min + b.max);
    const float r = 0.5f * glm::length(b.max - b.min);
    const float fov = 0.7f;
    const float d = r / std::sin(0.5f * std::min(fov, fov * aspect)) * 1.05f;
    const glm::vec3 eye = c + glm::normalize(glm::vec3(0.35f, 0.3f, 1.0f)) * d;
    aq::scene::Camera cam;
    const glm::vec3 f = glm::normalize(c - eye), sd = glm::normalize(glm::cross(f, glm::vec3(0, 1, 0)));
    const glm::vec3 u = glm::cross(sd, f);
    cam.view = glm::mat4(1.0f);
    cam.view[0][0] = sd.x; cam.view[1][0] = sd.y; cam.view[2][0] = sd.z;
    cam.view[0][1] = u.x;  cam.view[1][1] = u.y;  cam.view[2][1] = u.z;
    cam.view[0][2] = -f.x; cam.view[1][2] = -f.y; cam.view[2][2] = -f.z;
    cam.view[3][0] = -glm::dot(sd, eye);
    cam.view[3][1] = -glm::dot(u, eye);
    cam.view[3][2] = glm::dot(f, eye);
    cam.yfov = fov;
    cam.znear = d * 0.05f;
    cam.zfar = d * 3.0f;
    return cam;
}
}  // namespace

TEST(RasterHashDump, Dragon871k) {
    if (!std::getenv("AQ_RASTER_HASHDUMP")) GTEST_SKIP() << "set AQ_RASTER_HASHDUMP=1";
    const auto s = aq::scene::load_gltf(AQ_SHARED_DIR "/assets/meshes/stanford_dragon/dragon_871k.glb");
    for (bool cull : {false, true})
        for (int threads : {1, 2}) {
            aq::raster::RenderSettings st;
            st.width = 1920;
            st.height = 1080;
            st.exec = aq::Exec::fast(threads);
            st.frame = 1;
            st.cull_backfaces = cull;
            const aq::Targets t = aq::raster::render_gbuffer(s, bench_camera(s, 1920.0f / 1080.0f), st);
            for (const auto& [name, img] : t.all())
                std::printf("HASH cull=%d t=%d %s %s\n", int(cull), threads, name.c_str(),
                            aq::sha256_hex(img).c_str());
        }
}
