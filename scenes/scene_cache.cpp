// scenes/scene_cache.cpp — load_scene through the content cache.
#include "scenes/scene_cache.h"

#include <algorithm>
#include <filesystem>

#include "core/input.h"
#include "core/io.h"
#include "scenes/scene_archive.h"

namespace aq::scene {
namespace fs = std::filesystem;

namespace {

constexpr const char* kKind = "scene";

//! Every file the entry lists besides the scene itself still has its recorded bytes (read, and so
//! recorded as an input of this run, as the load would have).
bool inputs_unchanged(const std::vector<InputRecord>& deps, const std::string& scene_path) {
    for (const InputRecord& d : deps) {
        if (d.path == scene_path) continue;
        InputRecord now;
        try {
            (void)read_input_file(d.path, kMaxModelFileBytes, "input", &now);
        } catch (const Error&) {
            return false;
        }
        if (now.sha256 != d.sha256) return false;
    }
    return true;
}

}  // namespace

SceneDesc load_scene_cached(const std::string& spec, const LoadOptions& options, const cache::Store* store,
                            SceneCacheUse* use) {
    SceneCacheUse local;
    SceneCacheUse& u = use ? *use : local;
    u = {};
    if (!store || options.load_model || spec.rfind(kProceduralPrefix, 0) == 0) return load_scene(spec, options);
    std::error_code ec;
    const std::string abs = fs::absolute(spec, ec).lexically_normal().string();
    const std::string ext = lower_extension(spec);
    if (ec || (ext != ".json" && ext != ".gltf" && ext != ".glb")) return load_scene(spec, options);
    InputRecord self;
    try {
        (void)read_input_file(spec, ext == ".json" ? kMaxJsonFileBytes : kMaxModelFileBytes, "scene", &self);
    } catch (const Error&) {
        return load_scene(spec, options);  // the load reports it
    }
    u.key = cache::key({kKind, abs, self.sha256, options.allow_outside_files ? "outside" : "confined",
                        std::to_string(options.texture_budget_bytes), edits_key(options.edits)});

    std::string problem;
    if (std::optional<cache::Entry> e = store->find(kKind, u.key, &problem)) {
        SceneDesc d;
        bool unchanged = false;
        const std::string bad = store->read(kKind, u.key, *e, [&](archive::Reader& r) {
            std::vector<InputRecord> deps;
            r(deps);
            unchanged = inputs_unchanged(deps, self.path);
            if (unchanged) r(d);
            return unchanged;
        });
        if (!bad.empty()) {
            u.notes.push_back(bad);
        } else if (unchanged) {
            if (!d.paper.empty() && options.paper_known) options.paper_known(d.paper);
            u.hit = true;
            return d;
        }
    } else if (!problem.empty()) {
        u.notes.push_back(problem);
    }

    InputCapture capture;
    SceneDesc d = load_scene(spec, options);
    std::vector<InputRecord> deps = capture.records();
    std::sort(deps.begin(), deps.end(), [](const InputRecord& a, const InputRecord& b) { return a.path < b.path; });
    deps.erase(std::unique(deps.begin(), deps.end(), [](const InputRecord& a, const InputRecord& b) { return a.path == b.path; }),
               deps.end());
    const std::string why = store->store(kKind, u.key, [&](archive::Writer& w) { w(deps, d); });
    if (!why.empty()) u.notes.push_back(why);
    return d;
}

}  // namespace aq::scene
