// scenes/scene_cache.h — load_scene through the content cache (core/cache.h, docs/cache.md).
//
// The entry of a scene holds what load_scene returns (geometry, materials, decoded and
// mip-mapped textures, the scene file's settings, the loading warnings) and the list of files the
// load read, each with its SHA-256. Its key is the SHA-256 of the build, the scene's absolute path,
// its bytes and the load options that shape the result; a hit is used only when every other file
// it lists still has the recorded bytes (each is read and hashed again, as the provenance manifest
// needs anyway). So a changed texture or buffer is a miss, never a stale image.
#pragma once

#include <string>
#include <vector>

#include "core/cache.h"
#include "scenes/scene_file.h"

namespace aq::scene {

struct SceneCacheUse {
    std::string key;                   //!< the entry's key; empty: not cached (procedural scene, no cache)
    bool hit = false;                  //!< the scene came from the cache
    std::vector<std::string> notes;    //!< why an entry was not used or not stored (for warnings)
};

//! load_scene(spec, options), from `store` when it holds the scene's entry, else loaded and then
//! stored. `store` null: load_scene. The result is the same, member for member, either way.
SceneDesc load_scene_cached(const std::string& spec, const LoadOptions& options, const cache::Store* store,
                            SceneCacheUse* use = nullptr);

}  // namespace aq::scene
