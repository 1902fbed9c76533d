// scenes/gltf_loader.h — glTF 2.0 (.gltf, .glb, embedded data URIs) into the aq::scene model.
//
// Parsing is done by tinygltf; everything tinygltf does not check (accessor and bufferView ranges,
// strides, index values, counts, node cycles, non-finite transforms) is validated here before any
// byte is read, so hostile files end in an aq::Error and never in a crash. Images are kept as
// bytes by a tinygltf callback and decoded with OpenImageIO. Decisions (texture colour space,
// BLEND, fallbacks, limits) are documented in docs/scenes.md.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "core/io.h"
#include "scenes/scene.h"

namespace aq::scene {

//! Limits checked before allocating (docs/scenes.md "Limits").
inline constexpr std::size_t kMaxTriangles = 50'000'000;     //!< per file, after strip/fan expansion,
                                                             //!< and again after instancing
inline constexpr std::size_t kMaxVertices = 50'000'000;      //!< per accessor, and summed over
                                                             //!< the triangle primitives of a file
inline constexpr std::size_t kMaxFileBytes = 2'000'000'000;  //!< .gltf/.glb and each external buffer
//! Decoded texture bytes of one render (scene.h kMaxDecodedBytesPerRender): the model's textures
//! and the scene file's images share it.
inline constexpr std::size_t kMaxDecodedTextureBytes = kMaxDecodedBytesPerRender;
//! Accessor data read from one file (count x element size summed over every accessor use,
//! repeats included): 2 GiB.
inline constexpr std::size_t kMaxAccessorBytes = std::size_t(2) << 30;
//! An accessor without a bufferView is all zeros (glTF 2.0 §3.6.2.2): such implicit data is
//! limited to 16 MiB per file, so a tiny file cannot ask for gigabytes of zeros.
inline constexpr std::size_t kMaxImplicitAccessorBytes = std::size_t(16) << 20;

//! One edit of a scene file's art direction (render --scene-set POINTER=VALUE; the live page's
//! scene panel): the value at a JSON pointer of the file (RFC 6901, e.g. "/layers/1/color")
//! replaced by `value` (JSON text) before the file is read. Only the values scene_knobs lists may
//! be edited, each by one of its own kind (docs/scenes.md "Editing the art direction").
struct SceneEdit {
    std::string pointer;
    std::string value;
    bool operator==(const SceneEdit&) const = default;
};
//! Every pointer and value in order: what names a list of edits (cache keys, the live server).
inline std::string edits_key(const std::vector<SceneEdit>& edits) {
    std::string k;
    for (const SceneEdit& e : edits) k += e.pointer + '\n' + e.value + '\n';
    return k;
}

struct LoadOptions {
    //! Allow buffer and image URIs that resolve outside the model's folder (docs/limits.md
    //! "Path policy"; CLI --allow-outside-files).
    bool allow_outside_files = false;
    //! Budget for everything the render decodes: the file's textures, then the scene file's images
    //! (Scene::decode_budget; tests lower it; docs/limits.md).
    std::size_t texture_budget_bytes = kMaxDecodedTextureBytes;
    //! Scene files: called with the resolved path of the file's "paper" as soon as it is known,
    //! before the model loads, so a caller can decode it meanwhile (the CLI does; issue 13 item 3).
    std::function<void(const std::string& paper)> paper_known;
    //! Scene files: edits of their art direction, applied in order (SceneEdit). Anything else
    //! given edits is an error.
    std::vector<SceneEdit> edits;
    //! Scene files: where their model comes from; empty: load_gltf. A live server passes the model
    //! it loaded once, so an edit of the art direction does not read and decode the model again.
    std::function<Scene(const std::string& path, const LoadOptions& options)> load_model;
};
inline constexpr int kMaxNodeDepth = 1024;                   //!< node hierarchy depth

//! Loads a .gltf or .glb file (format chosen by the magic bytes, not the extension).
//! Every node of the default scene (else scene 0, else every root node) becomes an Instance with
//! object_id 1, 2, ... in depth-first order; every mesh of the file is converted and validated,
//! referenced or not. Cameras attached to nodes become Scene::cameras in the same order.
//! Non-fatal problems (skipped points/lines, missing textures, non-finite positions, ...) are
//! appended to Scene::warnings and, when given, to *warnings. Throws aq::Error naming the file.
Scene load_gltf(const std::string& path, std::vector<std::string>* warnings = nullptr,
                const LoadOptions& options = {});

//! Area-weighted vertex normals of an indexed triangle list (degenerate and non-finite triangles
//! contribute nothing; a vertex with no contribution gets +Z).
std::vector<glm::vec3> compute_normals(const std::vector<glm::vec3>& positions,
                                       const std::vector<std::uint32_t>& indices);

//! Per-vertex tangents (xyz, w = handedness) from per-triangle UV derivatives, accumulated and
//! Gram-Schmidt orthogonalised against the normal. Vertices without usable UVs get an arbitrary
//! tangent perpendicular to the normal (w = 1).
std::vector<glm::vec4> compute_tangents(const std::vector<glm::vec3>& positions,
                                        const std::vector<glm::vec3>& normals,
                                        const std::vector<glm::vec2>& uv,
                                        const std::vector<std::uint32_t>& indices);

//! Expands a glTF primitive topology into a triangle list. mode: 4 triangles, 5 strip, 6 fan.
//! Strips alternate winding so every triangle keeps the orientation of the first.
std::vector<std::uint32_t> to_triangle_list(int mode, const std::vector<std::uint32_t>& idx);

//! Decodes an encoded image (PNG, JPEG, ... anything OpenImageIO reads from memory) into RGBA
//! float with the stored values (no transfer curve). `name` is used for messages and to guess
//! the format. Throws aq::Error.
ImageF decode_image_bytes(const unsigned char* bytes, std::size_t size, const std::string& name,
                          DecodeBudget* budget = nullptr);

//! A texture (level 0, without mip levels: finish_texture builds them) from an encoded image held
//! in memory, every value mapped by `map`. An 8-bit file keeps level 0 as its codes (decoded
//! straight to 8-bit RGBA by core/png.h or core/jpeg.h, or found 8-bit after OpenImageIO's
//! decode), with the mapped value of each code: the values of the RGBA float image that
//! decode_image_bytes and the mapping would give, bit for bit, in a quarter of the bytes. Other
//! files keep RGBA float. `name` is used for messages and to guess the format. Throws aq::Error
//! (BudgetError past the budget).
Texture decode_texture(const std::string& name, const unsigned char* bytes, std::size_t size, DecodeBudget* budget,
                       const TexelMap& map = {});
//! decode_texture of an image file.
Texture read_texture(const std::string& path, DecodeBudget* budget, const TexelMap& map = {});

}  // namespace aq::scene
