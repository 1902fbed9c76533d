// tests/app/orbit_test.cpp — `render --orbit DEG` (app/render_job.h frame_camera): frame N's camera
// is the scene camera turned by N x DEG about the vertical axis through the centre of the scene's
// bounds — eye height and distance to that axis kept, the azimuth advanced by N x DEG, the view
// still aimed at the same point; frame 0 (or DEG = 0) is the camera itself.
#include <cmath>

#include <gtest/gtest.h>

#include "app/render_job.h"

namespace aq::app {
namespace {

glm::vec3 eye_of(const scene::Camera& c) { return glm::vec3(glm::inverse(c.view)[3]); }
glm::vec3 forward_of(const scene::Camera& c) { return -glm::vec3(glm::inverse(c.view)[2]); }

TEST(Orbit, TurnsTheCameraAboutTheVerticalAxisThroughTheBoundsCentre) {
    RenderOptions o;
    o.scene = "procedural:tree";
    o.style = "none";
    o.style_given = true;
    o.width = o.height = 64;
    o.orbit_deg = 30;
    const RenderJob job = prepare_render(o, Reporter{});
    const scene::Bounds b = job.desc.scene.world_bounds();
    const glm::vec3 c = 0.5f * (b.min + b.max);
    const scene::Camera c0 = frame_camera(job, 0);
    EXPECT_EQ(c0.view, job.desc.camera.view);
    const glm::vec3 e0 = eye_of(c0);
    const float r0 = std::hypot(e0.x - c.x, e0.z - c.z);
    const float a0 = std::atan2(e0.z - c.z, e0.x - c.x);
    for (int f : {1, 3, 12}) {
        const glm::vec3 e = eye_of(frame_camera(job, f));
        EXPECT_NEAR(e.y, e0.y, 1e-3f * r0) << f;
        EXPECT_NEAR(std::hypot(e.x - c.x, e.z - c.z), r0, 1e-3f * r0) << f;
        float da = std::atan2(e.z - c.z, e.x - c.x) - a0;
        const float want = float(f) * 30.0f * 3.14159265f / 180.0f;
        // either sense of rotation is an orbit; this one turns the eye by +30 degrees a frame about +Y
        // (right-handed: x towards -z), i.e. the angle in the x-z plane decreases.
        da = std::remainder(-da - want, 2.0f * 3.14159265f);
        EXPECT_NEAR(da, 0.0f, 1e-3f) << f;
        // still aimed at the same point: the centre's direction from the eye keeps its angle to the view axis
        const scene::Camera cf = frame_camera(job, f);
        const float cos0 = glm::dot(glm::normalize(c - e0), forward_of(c0));
        EXPECT_NEAR(glm::dot(glm::normalize(c - e), forward_of(cf)), cos0, 1e-4f) << f;
    }
}

}  // namespace
}  // namespace aq::app
