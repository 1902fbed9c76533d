// tests/app/orbit_test.cpp — `render --orbit DEG` (app/render_job.h frame_camera): frame N's camera
// is the scene camera turned by N x DEG about the vertical axis through the centre of the scene's
// bounds — eye height and distance to that axis kept, the azimuth advanced by N x DEG, the view
// still aimed at the same point; frame 0 (or DEG = 0) is the camera itself.
#include <cmath>

#include <gtest/gtest.h>

#include "app/render_job.h"
#include "raster/vertex.h"

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

// --view Y,P,Z,X,V: after the turn and the zoom, the pan moves the camera in its own plane so the
// bounds' centre lands at NDC (-X / aspect, -V); the view direction and the centre's depth stay.
TEST(View, PanPutsTheCentreWhereItSays) {
    RenderOptions o;
    o.scene = "procedural:tree";
    o.style = "none";
    o.style_given = true;
    o.width = 96;
    o.height = 64;
    o.view_yaw = 20;
    o.view_pitch = 10;
    o.view_zoom = 1.5;
    RenderJob job = prepare_render(o, Reporter{});
    const scene::Bounds b = job.desc.scene.world_bounds();
    const glm::vec3 c = 0.5f * (b.min + b.max);
    const scene::Camera still = frame_camera(job, 0);
    const float aspect = 96.0f / 64.0f;
    for (auto [x, y] : {std::pair{0.5, 0.0}, std::pair{0.0, -0.25}, std::pair{-1.2, 0.8}}) {
        job.options.view_pan_x = x;
        job.options.view_pan_y = y;
        const scene::Camera cam = frame_camera(job, 0);
        const glm::vec4 e = cam.view * glm::vec4(c, 1.0f);
        const glm::vec4 e0 = still.view * glm::vec4(c, 1.0f);
        EXPECT_NEAR(e.z, e0.z, 1e-4f * std::abs(e0.z));  // same depth
        EXPECT_EQ(forward_of(cam), forward_of(still));    // same direction
        const glm::vec4 clip = raster::projection_matrix(cam, aspect) * e;
        const glm::vec4 clip0 = raster::projection_matrix(still, aspect) * e0;
        EXPECT_NEAR(clip.x / clip.w - clip0.x / clip0.w, -x / aspect, 1e-4) << x << "," << y;
        EXPECT_NEAR(clip.y / clip.w - clip0.y / clip0.w, -y, 1e-4) << x << "," << y;
    }
}

}  // namespace
}  // namespace aq::app
