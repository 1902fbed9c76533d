// tests/reference/reference_scenes.h — the G-buffers the reference checks run on: scenes rendered
// by raster/ from the real models in ../shared/assets (through the scene files in scenes/data),
// the procedural swatches, and the synthetic G-buffer of tests/synthetic_gbuffer.h.
#pragma once

#include <string>
#include <vector>

#include "core/targets.h"
#include "raster/raster.h"
#include "reference/stage_inputs.h"
#include "tests/synthetic_gbuffer.h"
#include "scenes/scene_file.h"
#include "stylize/paper.h"
#include "tests/test_support.h"

namespace aq::ref {

struct ReferenceScene {
    std::string name;
    Targets gbuffer;
    glm::vec3 substrate_color{1.0f};
    stylize::PaperSpec paper;
    bool has_paper = false;
};

//! "synthetic", then scene files from scenes/data: three built from real models and the
//! procedural swatches.
inline std::vector<std::string> reference_scene_names() {
    return {"synthetic", "suzanne", "waterbottle", "orientation_test", "procedural"};
}

//! A scene file of scenes/data by name, or a bare glTF under ../shared/assets when the name ends
//! in .gltf/.glb (framed automatically, default light, neutral control).
inline scene::SceneDesc load_reference_scene(const std::string& name) {
    const auto ends = [&](const char* e) {
        const std::string x = e;
        return name.size() > x.size() && name.compare(name.size() - x.size(), x.size(), x) == 0;
    };
    if (ends(".gltf") || ends(".glb")) return scene::load_scene(test::asset(name));
    return scene::load_scene(test::source_dir() + "/scenes/data/" + name + ".json");
}

inline ReferenceScene make_reference_scene(const std::string& name, int w, int h) {
    ReferenceScene r;
    r.name = name;
    if (name == "synthetic") {
        r.gbuffer = aq::test::synthetic_gbuffer(w, h, 11);
        r.substrate_color = {0.98f, 0.96f, 0.9f};
        r.paper.file = test::asset("paper/mnpr/rough_default_2k.jpg");
        r.has_paper = true;
        return r;
    }
    scene::SceneDesc d = load_reference_scene(name);
    scene::Camera cam = d.camera;
    if (d.camera_auto) cam = scene::frame_bounds(d.scene.world_bounds(), float(w) / float(h), d.auto_view_dir, d.auto_yfov);
    raster::RenderSettings rs;
    rs.width = w;
    rs.height = h;
    rs.frame = 3;  // a non-zero tremor phase
    rs.substrate_color = d.substrate_color;
    r.gbuffer = raster::render_gbuffer(d.scene, cam, rs);
    r.substrate_color = d.substrate_color;
    if (!d.paper.empty()) {
        r.paper.file = d.paper;
        r.has_paper = true;
    }
    return r;
}

}  // namespace aq::ref
