// scenes/gltf_loader.cpp — glTF 2.0 into aq::scene::Scene, validating everything it reads: the
// file, its GLB container, the node tree and cameras (accessors and primitives: gltf_meshes.cpp;
// materials and textures: gltf_materials.cpp; shared: gltf_reader.h).
//
// tinygltf parses the JSON and loads buffers; it does not check that accessors, bufferViews and
// strides stay inside their buffers, nor index values, nor node cycles. The reader checks all of
// that (overflow-safe) before reading a byte, so every malformed input ends in an aq::Error.
// Images are not decoded by tinygltf: a callback keeps the encoded bytes and OpenImageIO decodes
// the ones a material uses (base colour, normal map), keeping stored values (docs/scenes.md).
#include "scenes/gltf_reader.h"

#include <algorithm>
#include <atomic>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <numeric>
#include <set>
#include <string_view>

#include <glm/gtc/quaternion.hpp>
#include <tbb/parallel_for.h>
#include <glm/gtc/type_ptr.hpp>
#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include "core/color.h"
#include "core/input.h"
#include "core/io.h"
#include "core/json_file.h"
#include "core/unorm8.h"
#include "scenes/material_params.h"


namespace aq::scene {
namespace {
namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------------
// Files: tinygltf's file-system callbacks, so external buffers and images go through the same
// rules as the model itself (core/input.h: regular files only, size-capped) and the path policy
// (inside the model's folder unless allowed; tinygltf also tries the working folder, which the
// policy refuses like any other outside path).

bool fs_exists(const std::string& p, void*) {
    // Existence only: the policy is enforced by fs_read, so a refused path gets a message that
    // explains the policy instead of tinygltf's "File not found".
    std::error_code ec;
    return fs::exists(p, ec);
}
std::string fs_expand(const std::string& p, void*) { return p; }
bool fs_read(std::vector<unsigned char>* out, std::string* err, const std::string& p, void* user) {
    if (const std::string why = path_policy_violation(*static_cast<const PathPolicy*>(user), p); !why.empty()) {
        if (err) *err += "'" + p + "': refused: " + why + "\n";
        return false;
    }
    try {
        *out = read_input_file(p, kMaxFileBytes, "file");
        return true;
    } catch (const Error& e) {
        if (err) *err += std::string(e.what()) + "\n";
        return false;
    }
}
bool fs_write(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    if (err) *err += "writing is disabled in the loader\n";
    return false;
}

// Keeps encoded bytes of URI / data-URI images. Images in bufferViews are skipped: tinygltf
// hands us a pointer it has not range-checked, so those bytes are fetched later through our own
// validated bufferView access.
bool keep_image_bytes(tinygltf::Image* img, const int, std::string*, std::string*, int, int,
                      const unsigned char* bytes, int size, void*) {
    if (img->bufferView >= 0) return true;
    if (bytes && size > 0) img->image.assign(bytes, bytes + size);
    img->as_is = true;
    return true;
}

// ---------------------------------------------------------------------------------------------

std::uint32_t le32(const unsigned char* p) {
    return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 |
           std::uint32_t(p[3]) << 24;
}

// Our own GLB container checks (before tinygltf sees the bytes).
void check_glb(const std::vector<unsigned char>& b, std::string* warn_out, const std::string& where) {
    auto fail = [&](const std::string& m) { throw Error(where + ": invalid GLB: " + m); };
    if (b.size() < 20) fail("truncated: " + std::to_string(b.size()) + " bytes, the header needs 20");
    const std::uint32_t version = le32(&b[4]), length = le32(&b[8]);
    const std::uint32_t c0len = le32(&b[12]), c0type = le32(&b[16]);
    if (version != 2) fail("container version " + std::to_string(version) + ", expected 2");
    if (length > b.size())
        fail("truncated: header says " + std::to_string(length) + " bytes, file has " +
             std::to_string(b.size()));
    if (length < b.size())
        *warn_out = "GLB header length " + std::to_string(length) + " is smaller than the file (" +
                    std::to_string(b.size()) + " bytes); trailing bytes ignored";
    if (length < 20) fail("header length " + std::to_string(length) + " is smaller than the header");
    if (c0type != 0x4E4F534Au) fail("first chunk is not JSON");
    if (c0len % 4 != 0) fail("JSON chunk length " + std::to_string(c0len) + " is not a multiple of 4");
    if (c0len == 0 || std::uint64_t(c0len) + 20 > length) fail("JSON chunk exceeds the file");
    std::uint64_t off = 20ull + c0len;
    off = (off + 3) & ~std::uint64_t(3);  // chunks are 4-byte aligned
    if (off + 8 <= length) {
        const std::uint32_t c1len = le32(&b[off]), c1type = le32(&b[off + 4]);
        if (c1type != 0x004E4942u) fail("second chunk is not BIN");
        if (off + 8 + std::uint64_t(c1len) > length) fail("BIN chunk exceeds the file");
    }
}

}  // namespace

namespace gltf {

// --- nodes and cameras -------------------------------------------------------------------------

void Loader::add_camera(const tinygltf::Camera& gc, const glm::mat4& world, const std::string& node_name) {
    Camera cam;
    cam.name = !gc.name.empty() ? gc.name : node_name;
    // glTF cameras look down -Z of their node; scale is not allowed on camera nodes, so it is
    // removed by orthonormalising the frame (Z kept, Y re-derived).
    const glm::vec3 eye(world[3]);
    glm::vec3 z(world[2]), y(world[1]);
    if (glm::length(z) < 1e-12f || glm::length(y) < 1e-12f) fail("camera node '" + node_name + "' has a degenerate transform");
    z = glm::normalize(z);
    glm::vec3 x = glm::cross(y, z);
    if (glm::length(x) < 1e-12f) fail("camera node '" + node_name + "' has a degenerate transform");
    x = glm::normalize(x);
    y = glm::cross(z, x);
    glm::mat4 cam_to_world(glm::vec4(x, 0.0f), glm::vec4(y, 0.0f), glm::vec4(z, 0.0f), glm::vec4(eye, 1.0f));
    cam.view = glm::inverse(cam_to_world);
    const std::string what = "camera '" + cam.name + "'";
    bool infinite = false;
    if (gc.type == "perspective") {
        const auto& p = gc.perspective;
        if (!(p.yfov > 0.0 && p.yfov < 3.14159)) fail(what + ": yfov " + std::to_string(p.yfov) + " outside (0, pi)");
        if (!(p.znear > 0.0 && std::isfinite(p.znear))) fail(what + ": znear must be > 0");
        cam.yfov = float(p.yfov);
        cam.znear = float(p.znear);
        if (p.zfar == 0.0) infinite = true;
        else if (!(p.zfar > p.znear) || !std::isfinite(p.zfar)) fail(what + ": zfar must be > znear");
        else cam.zfar = float(p.zfar);
        if (p.aspectRatio > 0.0 && std::isfinite(p.aspectRatio)) cam.aspect = float(p.aspectRatio);
    } else if (gc.type == "orthographic") {
        const auto& o = gc.orthographic;
        if (!(std::isfinite(o.xmag) && std::isfinite(o.ymag) && o.xmag != 0.0 && o.ymag != 0.0))
            fail(what + ": xmag and ymag must be finite and non-zero");
        if (!(o.znear >= 0.0 && std::isfinite(o.znear) && o.zfar > o.znear && std::isfinite(o.zfar)))
            fail(what + ": needs 0 <= znear < zfar");
        cam.orthographic = true;
        cam.xmag = float(std::abs(o.xmag));
        cam.ymag = float(std::abs(o.ymag));
        cam.znear = float(o.znear);
        cam.zfar = float(o.zfar);
    } else {
        fail(what + ": unknown camera type '" + gc.type + "'");
    }
    if (infinite) infinite_cameras_.push_back(scene_.cameras.size());
    scene_.cameras.push_back(cam);
}

void Loader::traverse(int index, const glm::mat4& parent, int depth) {
    if (index < 0 || std::size_t(index) >= m_.nodes.size())
        fail("node " + std::to_string(index) + " does not exist (the file has " + std::to_string(m_.nodes.size()) + ")");
    if (depth > kMaxNodeDepth) fail("node hierarchy deeper than " + std::to_string(kMaxNodeDepth));
    char& state = node_state_[std::size_t(index)];
    if (state == 1) fail("node " + std::to_string(index) + " is its own ancestor (cycle in the node hierarchy)");
    if (state == 2) fail("node " + std::to_string(index) + " has more than one parent");
    state = 1;
    const tinygltf::Node& n = m_.nodes[std::size_t(index)];
    const std::string what = "node " + std::to_string(index) + (n.name.empty() ? "" : " '" + n.name + "'");
    glm::mat4 local(1.0f);
    if (!n.matrix.empty()) {
        if (n.matrix.size() != 16) fail(what + ": matrix must have 16 values");
        local = checked_mat4(n.matrix);
        if (!finite(local)) fail(what + ": matrix has a non-finite value");
    } else {
        auto check = [&](const std::vector<double>& v, std::size_t size, const char* name) {
            if (v.empty()) return false;
            if (v.size() != size) fail(what + ": " + name + " must have " + std::to_string(size) + " values");
            for (double d : v)
                if (!std::isfinite(d)) fail(what + ": " + name + " has a non-finite value");
            return true;
        };
        glm::mat4 t(1.0f), r(1.0f), s(1.0f);
        if (check(n.translation, 3, "translation"))
            t[3] = glm::vec4(float(n.translation[0]), float(n.translation[1]), float(n.translation[2]), 1.0f);
        if (check(n.rotation, 4, "rotation")) {
            glm::quat q(float(n.rotation[3]), float(n.rotation[0]), float(n.rotation[1]), float(n.rotation[2]));
            const float len = glm::length(q);
            if (!(len > 1e-6f) || !std::isfinite(len)) fail(what + ": rotation is not a unit quaternion");
            r = glm::mat4_cast(q / len);
        }
        if (check(n.scale, 3, "scale")) s = glm::mat4(glm::vec4(float(n.scale[0]), 0, 0, 0), glm::vec4(0, float(n.scale[1]), 0, 0),
                                                      glm::vec4(0, 0, float(n.scale[2]), 0), glm::vec4(0, 0, 0, 1));
        local = t * r * s;
    }
    const glm::mat4 world = parent * local;
    if (!finite(world)) fail(what + ": world transform overflows");
    if (n.mesh >= 0) {
        if (std::size_t(n.mesh) >= m_.meshes.size())
            fail(what + ": mesh " + std::to_string(n.mesh) + " does not exist (the file has " +
                 std::to_string(m_.meshes.size()) + ")");
        // Instancing multiplies triangles: bound what the rasterizer will be asked to draw.
        std::size_t mesh_tris = 0;
        for (const Primitive& p : scene_.meshes[std::size_t(n.mesh)].primitives) mesh_tris += p.indices.size() / 3;
        if (mesh_tris > kMaxTriangles - instanced_triangles_)
            fail("more than " + std::to_string(kMaxTriangles) + " triangles after instancing (limit)");
        instanced_triangles_ += mesh_tris;
        Instance inst;
        inst.mesh = n.mesh;
        inst.world = world;
        inst.object_id = next_object_id_++;
        inst.name = !n.name.empty() ? n.name : scene_.meshes[std::size_t(n.mesh)].name;
        scene_.instances.push_back(inst);
    } else if (n.mesh != -1) {
        fail(what + ": invalid mesh index " + std::to_string(n.mesh));
    }
    if (n.camera >= 0) {
        if (std::size_t(n.camera) >= m_.cameras.size())
            fail(what + ": camera " + std::to_string(n.camera) + " does not exist");
        add_camera(m_.cameras[std::size_t(n.camera)], world, n.name.empty() ? what : n.name);
    }
    for (int c : n.children) traverse(c, world, depth + 1);
    state = 2;
}

Scene Loader::run() {
    scene_.source = path_;
    for (const std::string& ext : m_.extensionsRequired)
        if (ext == "KHR_draco_mesh_compression" || ext == "EXT_meshopt_compression" || ext == "KHR_texture_basisu")
            fail("required extension " + ext + " is not supported");
        else if (ext != "KHR_mesh_quantization")
            warn("required extension " + ext + " is ignored");
    if (!m_.skins.empty() || !m_.animations.empty()) warn("skins and animations are ignored (static bind pose)");

    // Which materials need tangents (normal map present and its image decodable).
    scene_.materials.reserve(m_.materials.size() + 1);
    for (std::size_t i = 0; i < m_.materials.size(); ++i) scene_.materials.push_back(convert_material(int(i)));
    decode_textures();
    for (const Material& m : scene_.materials) material_needs_tangents_.push_back(m.normal_texture.texture >= 0);
    convert_meshes();
    if (need_default_material_) {
        Material def;
        def.name = "default";
        def.linear_color = true;
        scene_.materials.push_back(def);
    }

    node_state_.assign(m_.nodes.size(), 0);
    std::vector<int> roots;
    if (!m_.scenes.empty()) {
        int si = m_.defaultScene;
        if (si < 0) si = 0;
        if (std::size_t(si) >= m_.scenes.size()) fail("default scene " + std::to_string(si) + " does not exist");
        roots = m_.scenes[std::size_t(si)].nodes;
    } else {
        // No scene: every node that is nobody's child is a root.
        std::vector<char> is_child(m_.nodes.size(), 0);
        for (const tinygltf::Node& n : m_.nodes)
            for (int c : n.children) {
                if (c < 0 || std::size_t(c) >= m_.nodes.size()) fail("node child " + std::to_string(c) + " does not exist");
                is_child[std::size_t(c)] = 1;
            }
        for (std::size_t i = 0; i < m_.nodes.size(); ++i)
            if (!is_child[i]) roots.push_back(int(i));
    }
    for (int r : roots) traverse(r, glm::mat4(1.0f), 0);

    if (nonfinite_positions_ > 0)
        warn(std::to_string(nonfinite_positions_) +
             " vertex positions are not finite; kept (the rasterizer drops their triangles)");
    if (!infinite_cameras_.empty()) {
        const Bounds b = scene_.world_bounds();
        for (std::size_t ci : infinite_cameras_) {
            Camera& c = scene_.cameras[ci];
            float far = c.znear * 1000.0f;
            if (b.valid) {
                const glm::mat4 inv = glm::inverse(c.view);
                const glm::vec3 eye(inv[3]);
                float d = 0.0f;
                for (int k = 0; k < 8; ++k) {
                    const glm::vec3 corner((k & 1) ? b.max.x : b.min.x, (k & 2) ? b.max.y : b.min.y,
                                           (k & 4) ? b.max.z : b.min.z);
                    d = std::max(d, glm::length(corner - eye));
                }
                far = std::max(d * 1.5f, c.znear * 2.0f);
            }
            c.zfar = far;
        }
    }
    scene_.warnings = warnings;
    scene_.decode_budget = texture_budget_;  // what is left for the scene file's images
    return std::move(scene_);
}

}  // namespace gltf

Scene load_gltf(const std::string& path, std::vector<std::string>* warnings, const LoadOptions& options) {
    std::vector<unsigned char> bytes = read_input_file(path, kMaxFileBytes, "glTF");
    const bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
    const std::string ext = fs::path(path).extension().string();
    if (!binary && (ext == ".glb" || ext == ".GLB"))
        throw Error("glTF '" + path + "': invalid GLB: " +
                    (bytes.size() < 4 ? "truncated (" + std::to_string(bytes.size()) + " bytes)" : std::string("bad magic")));
    std::string glb_warning;
    if (binary) {
        check_glb(bytes, &glb_warning, "glTF '" + path + "'");
        aq::check_json_depth(bytes.data() + 20, le32(&bytes[12]), "glTF '" + path + "'");
    } else {
        aq::check_json_depth(bytes.data(), bytes.size(), "glTF '" + path + "'");
    }

    tinygltf::TinyGLTF gltf;
    gltf.SetImageLoader(keep_image_bytes, nullptr);
    gltf.SetStoreOriginalJSONForExtrasAndExtensions(true);
    PathPolicy policy;
    policy.root = fs::path(path).parent_path();
    policy.allow_outside = options.allow_outside_files;
    tinygltf::FsCallbacks cb{fs_exists, fs_expand, fs_read, fs_write, &policy};
    gltf.SetFsCallbacks(cb);
    tinygltf::Model model;
    std::string terr, twarn;
    std::string base_dir = fs::path(path).parent_path().string();
    if (base_dir.empty()) base_dir = ".";
    bool ok = false;
    try {
        if (binary)
            ok = gltf.LoadBinaryFromMemory(&model, &terr, &twarn, bytes.data(), static_cast<unsigned>(bytes.size()), base_dir);
        else
            ok = gltf.LoadASCIIFromString(&model, &terr, &twarn, reinterpret_cast<const char*>(bytes.data()),
                                          static_cast<unsigned>(bytes.size()), base_dir);
    } catch (const std::exception& e) {
        throw Error("glTF '" + path + "': parse error: " + e.what());
    }
    bytes.clear();
    bytes.shrink_to_fit();
    auto trim = [](std::string s) {
        while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
        for (char& c : s)
            if (c == '\n') c = ';';
        return s;
    };
    if (!ok) throw Error("glTF '" + path + "': " + (terr.empty() ? std::string("cannot be parsed") : trim(terr)));

    gltf::Loader loader(path, model, options.texture_budget_bytes);
    if (!glb_warning.empty()) loader.warnings.push_back("glTF '" + path + "': " + glb_warning);
    if (!twarn.empty()) loader.warnings.push_back("glTF '" + path + "': " + trim(twarn));
    Scene s;
    try {
        s = loader.run();
    } catch (const std::bad_alloc&) {
        throw Error("glTF '" + path + "': out of memory");
    }
    if (warnings) warnings->insert(warnings->end(), s.warnings.begin(), s.warnings.end());
    return s;
}

}  // namespace aq::scene
