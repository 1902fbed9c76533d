// scenes/gltf_loader.cpp — glTF 2.0 into aq::scene::Scene, validating everything it reads.
//
// tinygltf parses the JSON and loads buffers; it does not check that accessors, bufferViews and
// strides stay inside their buffers, nor index values, nor node cycles. This file checks all of
// that (overflow-safe) before reading a byte, so every malformed input ends in an aq::Error.
// Images are not decoded by tinygltf: a callback keeps the encoded bytes and OpenImageIO decodes
// the ones a material uses (base colour, normal map), keeping stored values (docs/scenes.md).
#include "scenes/gltf_loader.h"

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

int component_size(int ct) {
    switch (ct) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
        default: return 0;
    }
}

int num_components(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR: return 1;
        case TINYGLTF_TYPE_VEC2: return 2;
        case TINYGLTF_TYPE_VEC3: return 3;
        case TINYGLTF_TYPE_VEC4: return 4;
        case TINYGLTF_TYPE_MAT2: return 4;
        case TINYGLTF_TYPE_MAT3: return 9;
        case TINYGLTF_TYPE_MAT4: return 16;
        default: return 0;
    }
}

const char* type_name(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR: return "SCALAR";
        case TINYGLTF_TYPE_VEC2: return "VEC2";
        case TINYGLTF_TYPE_VEC3: return "VEC3";
        case TINYGLTF_TYPE_VEC4: return "VEC4";
        default: return "MAT";
    }
}

//! A validated accessor: every element i lies in [base + i*stride, base + i*stride + elem).
struct AccessorView {
    const unsigned char* base = nullptr;  //!< nullptr: no bufferView, all zeros (glTF rule)
    std::size_t count = 0, stride = 0;
    int comp_type = 0, ncomp = 0;
    bool normalized = false;

    float component(std::size_t i, int c) const {
        if (!base) return 0.0f;
        const unsigned char* p = base + i * stride + std::size_t(c) * component_size(comp_type);
        switch (comp_type) {
            case TINYGLTF_COMPONENT_TYPE_FLOAT: {
                float f;
                std::memcpy(&f, p, 4);
                return f;
            }
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
                const float v = float(p[0]);
                return normalized ? v / 255.0f : v;
            }
            case TINYGLTF_COMPONENT_TYPE_BYTE: {
                const float v = float(std::int8_t(p[0]));
                return normalized ? std::max(v / 127.0f, -1.0f) : v;
            }
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
                std::uint16_t u;
                std::memcpy(&u, p, 2);
                return normalized ? float(u) / 65535.0f : float(u);
            }
            case TINYGLTF_COMPONENT_TYPE_SHORT: {
                std::int16_t s;
                std::memcpy(&s, p, 2);
                return normalized ? std::max(float(s) / 32767.0f, -1.0f) : float(s);
            }
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
                std::uint32_t u;
                std::memcpy(&u, p, 4);
                return float(u);
            }
            default: return 0.0f;
        }
    }
    std::uint32_t index(std::size_t i) const {
        if (!base) return 0;
        const unsigned char* p = base + i * stride;
        switch (comp_type) {
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return p[0];
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
                std::uint16_t u;
                std::memcpy(&u, p, 2);
                return u;
            }
            default: {
                std::uint32_t u;
                std::memcpy(&u, p, 4);
                return u;
            }
        }
    }
};

glm::mat4 checked_mat4(const std::vector<double>& m) {
    glm::mat4 r;
    for (int i = 0; i < 16; ++i) glm::value_ptr(r)[i] = float(m[std::size_t(i)]);
    return r;
}

bool finite(const glm::mat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}

// ---------------------------------------------------------------------------------------------

class Loader {
public:
    Loader(const std::string& path, const tinygltf::Model& m, std::size_t texture_budget)
        : path_(path), m_(m), texture_budget_(render_decode_budget(texture_budget)) {}

    Scene run();
    std::vector<std::string> warnings;

private:
    [[noreturn]] void fail(const std::string& msg) const { throw Error("glTF '" + path_ + "': " + msg); }
    void warn(const std::string& msg) { warnings.push_back("glTF '" + path_ + "': " + msg); }

    AccessorView accessor(int index, const std::string& what);
    std::pair<const unsigned char*, std::size_t> buffer_view_bytes(int index, const std::string& what) const;
    Material convert_material(int index);
    TextureRef texture_ref(int tex_index, int texcoord, bool srgb, const std::string& what);
    //! A texture texture_ref will decode: its image's bytes, and the slot of scene_.textures it fills.
    struct PendingTexture {
        std::string label, what, fallback;
        const unsigned char* bytes;
        std::size_t size;
        bool srgb;
        int slot;
    };
    void decode_one(const PendingTexture& p, DecodeBudget* budget, Texture& out);
    void decode_textures();
    void convert_meshes();
    bool convert_primitive(const tinygltf::Primitive& gp, const std::string& where, Primitive& out);
    //! The primitive's triangle list from its indices (or 0..n-1), every index checked against n.
    void primitive_indices(const tinygltf::Primitive& gp, const std::string& where, int mode, std::size_t n, Primitive& out);
    //! Attribute `name` of the primitive when present (count n, one of `types`; integer colours
    //! normalised), else an empty view.
    AccessorView primitive_attribute(const tinygltf::Primitive& gp, const std::string& where, const std::string& name,
                                     std::initializer_list<int> types, bool colour, std::size_t n);
    //! NORMAL (else computed), TEXCOORD_0, COLOR_0 and the further attributes the scene file's
    //! control mapping may read (COLOR_n, TEXCOORD_n, _CUSTOM).
    void primitive_attributes(const tinygltf::Primitive& gp, const std::string& where, std::size_t n, Primitive& out);
    //! The primitive's material (the default one appended when it has none) and, where its
    //! material needs them, tangents (TANGENT, else computed).
    void primitive_material(const tinygltf::Primitive& gp, const std::string& where, std::size_t n, Primitive& out);
    void traverse(int node, const glm::mat4& parent, int depth);
    void add_camera(const tinygltf::Camera& gc, const glm::mat4& world, const std::string& node_name);

    std::string path_;
    const tinygltf::Model& m_;
    Scene scene_;
    std::map<std::pair<int, bool>, int> texture_cache_;  //!< (image, srgb) -> scene texture or -1
    std::vector<bool> material_needs_tangents_;
    bool need_default_material_ = false;
    std::size_t total_triangles_ = 0, instanced_triangles_ = 0, nonfinite_positions_ = 0;
    std::vector<char> node_state_;  //!< 0 unvisited, 1 on the current path, 2 done
    std::uint32_t next_object_id_ = 1;
    std::vector<std::size_t> infinite_cameras_;
    DecodeBudget texture_budget_;
    std::vector<PendingTexture> pending_;
    std::size_t accessor_bytes_ = 0, implicit_accessor_bytes_ = 0;
};

std::pair<const unsigned char*, std::size_t> Loader::buffer_view_bytes(int index,
                                                                     const std::string& what) const {
    if (index < 0 || std::size_t(index) >= m_.bufferViews.size())
        fail(what + ": bufferView " + std::to_string(index) + " does not exist (the file has " +
             std::to_string(m_.bufferViews.size()) + ")");
    const tinygltf::BufferView& bv = m_.bufferViews[std::size_t(index)];
    if (bv.buffer < 0 || std::size_t(bv.buffer) >= m_.buffers.size())
        fail(what + ": bufferView " + std::to_string(index) + " refers to buffer " +
             std::to_string(bv.buffer) + " which does not exist (the file has " +
             std::to_string(m_.buffers.size()) + ")");
    const std::vector<unsigned char>& data = m_.buffers[std::size_t(bv.buffer)].data;
    if (bv.byteOffset > data.size() || bv.byteLength > data.size() - bv.byteOffset)
        fail(what + ": bufferView " + std::to_string(index) + " [offset " + std::to_string(bv.byteOffset) +
             ", length " + std::to_string(bv.byteLength) + "] exceeds buffer " + std::to_string(bv.buffer) +
             " of " + std::to_string(data.size()) + " bytes");
    return {data.data() + bv.byteOffset, bv.byteLength};
}

AccessorView Loader::accessor(int index, const std::string& what) {
    if (index < 0 || std::size_t(index) >= m_.accessors.size())
        fail(what + ": accessor " + std::to_string(index) + " does not exist (the file has " +
             std::to_string(m_.accessors.size()) + ")");
    const tinygltf::Accessor& a = m_.accessors[std::size_t(index)];
    const std::string name = what + ": accessor " + std::to_string(index);
    if (a.sparse.isSparse) fail(name + " is sparse; sparse accessors are not supported");
    const int csize = component_size(a.componentType);
    if (csize == 0) fail(name + " has invalid componentType " + std::to_string(a.componentType));
    const int nc = num_components(a.type);
    if (nc == 0) fail(name + " has an invalid type");
    if (a.count > kMaxVertices)
        fail(name + " has count " + std::to_string(a.count) + ", above the limit of " +
             std::to_string(kMaxVertices));
    AccessorView v;
    v.count = a.count;
    v.comp_type = a.componentType;
    v.ncomp = nc;
    v.normalized = a.normalized;
    const std::size_t elem = std::size_t(csize) * std::size_t(nc);
    v.stride = elem;
    const std::size_t data_bytes = a.count * elem;  // count <= kMaxVertices: no overflow
    accessor_bytes_ += data_bytes;
    if (accessor_bytes_ > kMaxAccessorBytes)
        fail(name + ": the accessors read so far hold " + std::to_string(accessor_bytes_) +
             " bytes, above the limit of " + std::to_string(kMaxAccessorBytes) + " per file (docs/limits.md)");
    if (a.bufferView == -1) {  // no bufferView: zeros (glTF 2.0 §3.6.2.2)
        implicit_accessor_bytes_ += data_bytes;
        if (implicit_accessor_bytes_ > kMaxImplicitAccessorBytes)
            fail(name + " has no bufferView (implicit zeros) and count " + std::to_string(a.count) +
                 ": implicit accessor data above " + std::to_string(kMaxImplicitAccessorBytes) +
                 " bytes per file is refused (docs/limits.md)");
        return v;
    }
    const auto [bytes, length] = buffer_view_bytes(a.bufferView, name);
    const tinygltf::BufferView& bv = m_.bufferViews[std::size_t(a.bufferView)];
    if (bv.byteStride != 0) {
        if (bv.byteStride < elem || bv.byteStride > 252)
            fail(name + ": byteStride " + std::to_string(bv.byteStride) + " of bufferView " +
                 std::to_string(a.bufferView) + " is invalid for " + std::to_string(elem) +
                 "-byte elements (allowed: element size..252)");
        v.stride = bv.byteStride;
    }
    if (a.count > 0) {
        // offset + (count-1)*stride + elem <= length, without overflow.
        if (a.byteOffset > length || length - a.byteOffset < elem ||
            (a.count - 1) > (length - a.byteOffset - elem) / v.stride)
            fail(name + " (offset " + std::to_string(a.byteOffset) + ", count " + std::to_string(a.count) +
                 ", stride " + std::to_string(v.stride) + ") exceeds bufferView " +
                 std::to_string(a.bufferView) + " of " + std::to_string(length) + " bytes");
    }
    v.base = bytes + a.byteOffset;
    return v;
}

// --- images and textures -------------------------------------------------------------------------

TextureRef Loader::texture_ref(int tex_index, int texcoord, bool srgb, const std::string& what) {
    TextureRef ref;
    if (tex_index < 0) return ref;
    if (std::size_t(tex_index) >= m_.textures.size())
        fail(what + ": texture " + std::to_string(tex_index) + " does not exist (the file has " +
             std::to_string(m_.textures.size()) + ")");
    const tinygltf::Texture& t = m_.textures[std::size_t(tex_index)];
    if (texcoord != 0)
        warn(what + ": uses TEXCOORD_" + std::to_string(texcoord) + "; only TEXCOORD_0 is loaded, used instead");
    if (t.sampler >= 0) {
        if (std::size_t(t.sampler) >= m_.samplers.size())
            fail(what + ": sampler " + std::to_string(t.sampler) + " does not exist");
        const tinygltf::Sampler& s = m_.samplers[std::size_t(t.sampler)];
        auto wrap = [&](int w) {
            switch (w) {
                case TINYGLTF_TEXTURE_WRAP_REPEAT: return Wrap::Repeat;
                case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: return Wrap::ClampToEdge;
                case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: return Wrap::MirroredRepeat;
                default:
                    warn(what + ": unknown wrap mode " + std::to_string(w) + ", REPEAT used");
                    return Wrap::Repeat;
            }
        };
        ref.sampler.wrap_s = wrap(s.wrapS);
        ref.sampler.wrap_t = wrap(s.wrapT);
        ref.sampler.mag = s.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST ? Filter::Nearest : Filter::Linear;
        // minFilter (GL's names: FILTER_MIPMAP_MIP): the filter within a level and between levels.
        // Undefined (or unknown) is trilinear (scene.h Sampler).
        auto min_mip = [&](Filter f, MipFilter m) { ref.sampler.min = f, ref.sampler.mip = m; };
        switch (s.minFilter) {
            case TINYGLTF_TEXTURE_FILTER_NEAREST: min_mip(Filter::Nearest, MipFilter::None); break;
            case TINYGLTF_TEXTURE_FILTER_LINEAR: min_mip(Filter::Linear, MipFilter::None); break;
            case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_NEAREST: min_mip(Filter::Nearest, MipFilter::Nearest); break;
            case TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_NEAREST: min_mip(Filter::Linear, MipFilter::Nearest); break;
            case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_LINEAR: min_mip(Filter::Nearest, MipFilter::Linear); break;
            default: min_mip(Filter::Linear, MipFilter::Linear); break;
        }
    }
    const std::string fallback = srgb ? "white base colour" : "flat normal";
    if (t.source < 0) {
        warn(what + ": texture " + std::to_string(tex_index) + " has no image; treated as absent (" +
             fallback + ")");
        return ref;
    }
    if (std::size_t(t.source) >= m_.images.size())
        fail(what + ": image " + std::to_string(t.source) + " does not exist (the file has " +
             std::to_string(m_.images.size()) + ")");
    const auto key = std::make_pair(t.source, srgb);
    if (auto it = texture_cache_.find(key); it != texture_cache_.end()) {
        ref.texture = it->second;
        return ref;
    }
    const tinygltf::Image& img = m_.images[std::size_t(t.source)];
    std::string label = !img.uri.empty() ? img.uri : !img.name.empty() ? img.name : "image " + std::to_string(t.source);
    if (label.rfind("data:", 0) == 0) label = "embedded image " + std::to_string(t.source);
    int result = -1;
    const unsigned char* bytes = nullptr;
    std::size_t size = 0;
    if (img.bufferView >= 0) {
        const auto bv = buffer_view_bytes(img.bufferView, what + ": image " + std::to_string(t.source));
        bytes = bv.first;
        size = bv.second;
    } else {
        bytes = img.image.data();
        size = img.image.size();
    }
    if (size == 0) {
        warn(what + ": texture '" + label + "' is missing or unreadable; treated as absent (" + fallback + ")");
    } else {
        // Decoded with the others once every material is read (decode_textures); until then the
        // texture is an empty slot.
        result = int(scene_.textures.size());
        scene_.textures.emplace_back();
        pending_.push_back({label, what, fallback, bytes, size, srgb, result});
    }
    texture_cache_[key] = result;
    ref.texture = result;
    return ref;
}

void Loader::decode_one(const PendingTexture& p, DecodeBudget* budget, Texture& out) {
    // glTF §3.9.2: base colour textures are sRGB-encoded, decoded to linear.
    out = decode_texture(p.label, p.bytes, p.size, budget, {p.srgb ? TexelMap::Kind::Srgb : TexelMap::Kind::Identity});
    out.srgb = p.srgb;
    finish_texture(out);
}

void Loader::decode_textures() {
    const std::size_t n = pending_.size();
    if (n == 0) return;
    // In parallel, each texture within an equal share of the budget, so that together they stay
    // within it; results taken in file order. If one needs more than its share, everything is
    // decoded again one by one against the budget itself, as a sequential loader would (the same
    // textures, warnings and error, whatever the timing).
    std::vector<Texture> decoded(n);
    std::vector<std::string> errors(n);
    std::vector<std::size_t> charged(n, 0);
    std::atomic<bool> over_share{false};
    const std::size_t share = texture_budget_.bytes_left / n;
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
        DecodeBudget b{share, texture_budget_.what};
        try {
            decode_one(pending_[i], &b, decoded[i]);
            charged[i] = share - b.bytes_left;
        } catch (const BudgetError&) {
            over_share = true;
        } catch (const Error& e) {
            errors[i] = e.what();
        }
    });
    for (std::size_t i = 0; i < n; ++i) {
        const PendingTexture& p = pending_[i];
        Texture& slot = scene_.textures[std::size_t(p.slot)];
        try {
            if (over_share) {
                decode_one(p, &texture_budget_, slot);
            } else if (errors[i].empty()) {
                texture_budget_.bytes_left -= charged[i];  // the shares sum to at most the budget
                slot = std::move(decoded[i]);
            } else {
                throw Error(errors[i]);
            }
        } catch (const BudgetError& e) {
            fail(p.what + ": " + e.what());
        } catch (const Error& e) {
            warn(p.what + ": texture '" + p.label + "' cannot be decoded (" + e.what() + "); treated as absent (" +
                 p.fallback + ")");
            slot = Texture{};
        }
    }
    // Drop the slots of textures that could not be decoded; renumber the materials' references.
    std::vector<int> index(scene_.textures.size(), -1);
    std::vector<Texture> kept;
    for (std::size_t i = 0; i < scene_.textures.size(); ++i)
        if (!scene_.textures[i].empty()) {
            index[i] = int(kept.size());
            kept.push_back(std::move(scene_.textures[i]));
        }
    scene_.textures = std::move(kept);
    for (Material& m : scene_.materials)
        for (TextureRef* r : {&m.base_color_texture, &m.normal_texture})
            if (r->texture >= 0) r->texture = index[std::size_t(r->texture)];
    pending_.clear();
}

Material Loader::convert_material(int index) {
    const tinygltf::Material& gm = m_.materials[std::size_t(index)];
    const std::string what = "material " + std::to_string(index) + (gm.name.empty() ? "" : " '" + gm.name + "'");
    Material mat;
    mat.name = gm.name.empty() ? "material_" + std::to_string(index) : gm.name;
    mat.linear_color = true;  // glTF §3.9.2: baseColorFactor and COLOR_n are linear
    const auto& f = gm.pbrMetallicRoughness.baseColorFactor;
    if (f.size() != 4) fail(what + ": baseColorFactor must have 4 values");
    for (int i = 0; i < 4; ++i) {
        if (!std::isfinite(f[std::size_t(i)])) fail(what + ": baseColorFactor is not finite");
        mat.base_color[i] = float(std::clamp(f[std::size_t(i)], 0.0, 1.0));
    }
    mat.base_color_texture = texture_ref(gm.pbrMetallicRoughness.baseColorTexture.index,
                                         gm.pbrMetallicRoughness.baseColorTexture.texCoord, true,
                                         what + " base colour");
    mat.normal_texture = texture_ref(gm.normalTexture.index, gm.normalTexture.texCoord, false, what + " normal map");
    mat.normal_texture.scale = std::isfinite(gm.normalTexture.scale) ? float(gm.normalTexture.scale) : 1.0f;
    if (gm.alphaMode == "OPAQUE" || gm.alphaMode.empty()) mat.alpha_mode = AlphaMode::Opaque;
    else if (gm.alphaMode == "MASK") mat.alpha_mode = AlphaMode::Mask;
    else if (gm.alphaMode == "BLEND") mat.alpha_mode = AlphaMode::Blend;
    else {
        warn(what + ": unknown alphaMode '" + gm.alphaMode + "', OPAQUE used");
        mat.alpha_mode = AlphaMode::Opaque;
    }
    mat.alpha_cutoff = std::isfinite(gm.alphaCutoff) ? float(std::clamp(gm.alphaCutoff, 0.0, 1.0)) : 0.5f;
    mat.double_sided = gm.doubleSided;
    if (!gm.extras_json_string.empty()) {
        nlohmann::json ex = nlohmann::json::parse(gm.extras_json_string, nullptr, false);
        if (ex.is_object()) {
            std::vector<std::string> w;
            const std::string where = "glTF '" + path_ + "' " + what;
            if (ex.contains("watercolor"))
                detail::apply_watercolor_json(mat.wc, ex["watercolor"], where, "extras.watercolor.", false, &w);
            else
                detail::apply_watercolor_json(mat.wc, ex, where, "extras.", false, &w);
            for (auto& s : w) warnings.push_back(s);
        }
    }
    return mat;
}

// --- meshes ------------------------------------------------------------------------------------

bool Loader::convert_primitive(const tinygltf::Primitive& gp, const std::string& where, Primitive& out) {
    const int mode = gp.mode < 0 ? TINYGLTF_MODE_TRIANGLES : gp.mode;
    if (mode == TINYGLTF_MODE_POINTS || mode == TINYGLTF_MODE_LINE || mode == TINYGLTF_MODE_LINE_LOOP ||
        mode == TINYGLTF_MODE_LINE_STRIP) {
        warn(where + ": points/lines primitive (mode " + std::to_string(mode) + ") skipped");
        return false;
    }
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN)
        fail(where + ": invalid primitive mode " + std::to_string(mode));
    if (!gp.targets.empty()) warn(where + ": morph targets ignored");

    auto attr = gp.attributes.find("POSITION");
    if (attr == gp.attributes.end()) fail(where + ": no POSITION attribute");
    const AccessorView pos = accessor(attr->second, where + " POSITION");
    if (pos.ncomp != 3 || m_.accessors[std::size_t(attr->second)].type != TINYGLTF_TYPE_VEC3)
        fail(where + " POSITION: expected VEC3");
    const std::size_t n = pos.count;

    primitive_indices(gp, where, mode, n, out);
    out.positions.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        out.positions[i] = {pos.component(i, 0), pos.component(i, 1), pos.component(i, 2)};
        if (!std::isfinite(out.positions[i].x) || !std::isfinite(out.positions[i].y) ||
            !std::isfinite(out.positions[i].z))
            ++nonfinite_positions_;
    }

    primitive_attributes(gp, where, n, out);
    primitive_material(gp, where, n, out);
    return true;
}

void Loader::primitive_indices(const tinygltf::Primitive& gp, const std::string& where, int mode, std::size_t n, Primitive& out) {
    // Index count and triangle count are known before anything is allocated.
    std::size_t nidx = n;
    AccessorView iv;
    if (gp.indices >= 0) {
        iv = accessor(gp.indices, where + " indices");
        if (m_.accessors[std::size_t(gp.indices)].type != TINYGLTF_TYPE_SCALAR ||
            (iv.comp_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
             iv.comp_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
             iv.comp_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
            fail(where + " indices: expected SCALAR unsigned byte/short/int");
        nidx = iv.count;
    } else if (gp.indices != -1) {
        fail(where + ": invalid indices accessor " + std::to_string(gp.indices));
    }
    const std::size_t ntri = mode == TINYGLTF_MODE_TRIANGLES ? nidx / 3 : (nidx >= 3 ? nidx - 2 : 0);
    if (ntri > kMaxTriangles - total_triangles_)
        fail(where + ": more than " + std::to_string(kMaxTriangles) + " triangles in the file (limit)");
    total_triangles_ += ntri;

    std::vector<std::uint32_t> idx(nidx);
    if (gp.indices >= 0) {
        for (std::size_t i = 0; i < nidx; ++i) {
            idx[i] = iv.index(i);
            if (idx[i] >= n)
                fail(where + " indices: index " + std::to_string(idx[i]) + " at position " + std::to_string(i) +
                     " is out of range (" + std::to_string(n) + " vertices)");
        }
    } else {
        std::iota(idx.begin(), idx.end(), 0u);
    }
    if (mode == TINYGLTF_MODE_TRIANGLES && nidx % 3 != 0)
        warn(where + ": " + std::to_string(nidx % 3) + " trailing indices do not form a triangle, ignored");
    out.indices = to_triangle_list(mode, idx);
    idx.clear();
    idx.shrink_to_fit();

}

AccessorView Loader::primitive_attribute(const tinygltf::Primitive& gp, const std::string& where, const std::string& name,
                                         std::initializer_list<int> types, bool colour, std::size_t n) {
    auto it = gp.attributes.find(name);
    if (it == gp.attributes.end()) return {};
    AccessorView v = accessor(it->second, where + " " + name);
    const int t = m_.accessors[std::size_t(it->second)].type;
    if (std::find(types.begin(), types.end(), t) == types.end()) fail(where + " " + name + ": unexpected type " + type_name(t));
    if (v.count != n)
        fail(where + " " + name + ": count " + std::to_string(v.count) + " differs from POSITION count " + std::to_string(n));
    // Integer colours are normalised by definition (glTF 2.0 §3.7.2.1), whatever the flag says.
    if (colour && v.comp_type != TINYGLTF_COMPONENT_TYPE_FLOAT) v.normalized = true;
    return v;
}

void Loader::primitive_attributes(const tinygltf::Primitive& gp, const std::string& where, std::size_t n, Primitive& out) {
    auto read_attr = [&](const std::string& name, std::initializer_list<int> types, bool colour) {
        return primitive_attribute(gp, where, name, types, colour, n);
    };
    if (AccessorView v = read_attr("NORMAL", {TINYGLTF_TYPE_VEC3}, false); v.count) {
        out.normals.resize(n);
        for (std::size_t i = 0; i < n; ++i) out.normals[i] = {v.component(i, 0), v.component(i, 1), v.component(i, 2)};
    } else {
        out.normals = compute_normals(out.positions, out.indices);
    }
    if (AccessorView v = read_attr("TEXCOORD_0", {TINYGLTF_TYPE_VEC2}, false); v.count) {
        out.uv0.resize(n);
        for (std::size_t i = 0; i < n; ++i) out.uv0[i] = {v.component(i, 0), v.component(i, 1)};
    }
    if (AccessorView v = read_attr("COLOR_0", {TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4}, true); v.count) {
        out.colors.resize(n);
        for (std::size_t i = 0; i < n; ++i)
            out.colors[i] = {v.component(i, 0), v.component(i, 1), v.component(i, 2), v.ncomp == 4 ? v.component(i, 3) : 1.0f};
    }
    // Further attributes the scene file's control mapping may read (COLOR_n, TEXCOORD_n, _CUSTOM).
    for (const auto& [name, acc] : gp.attributes) {
        (void)acc;
        const bool colour = name.rfind("COLOR_", 0) == 0;
        if (!(colour && name != "COLOR_0") && !(name.rfind("TEXCOORD_", 0) == 0 && name != "TEXCOORD_0") &&
            !(name.rfind("_", 0) == 0))
            continue;
        AccessorView v = read_attr(name, {TINYGLTF_TYPE_SCALAR, TINYGLTF_TYPE_VEC2, TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4}, colour);
        auto& dst = out.attributes[name];
        dst.resize(n);
        for (std::size_t i = 0; i < n; ++i) {
            glm::vec4 c(0.0f, 0.0f, 0.0f, colour ? 1.0f : 0.0f);
            for (int k = 0; k < v.ncomp; ++k) c[k] = v.component(i, k);
            dst[i] = c;
        }
    }

}

void Loader::primitive_material(const tinygltf::Primitive& gp, const std::string& where, std::size_t n, Primitive& out) {
    if (gp.material >= 0) {
        if (std::size_t(gp.material) >= m_.materials.size())
            fail(where + ": material " + std::to_string(gp.material) + " does not exist (the file has " +
                 std::to_string(m_.materials.size()) + ")");
        out.material = gp.material;
    } else {
        if (gp.material != -1) fail(where + ": invalid material index " + std::to_string(gp.material));
        out.material = int(m_.materials.size());  // the default material, appended after the file's
        need_default_material_ = true;
    }
    if (out.material < int(material_needs_tangents_.size()) && material_needs_tangents_[std::size_t(out.material)]) {
        if (AccessorView v = primitive_attribute(gp, where, "TANGENT", {TINYGLTF_TYPE_VEC4}, false, n); v.count) {
            out.tangents.resize(n);
            for (std::size_t i = 0; i < n; ++i)
                out.tangents[i] = {v.component(i, 0), v.component(i, 1), v.component(i, 2), v.component(i, 3)};
        } else {
            if (out.uv0.empty())
                warn(where + ": normal-mapped material without TEXCOORD_0; tangents are arbitrary");
            out.tangents = compute_tangents(out.positions, out.normals, out.uv0, out.indices);
        }
    }
}

void Loader::convert_meshes() {
    // Pre-pass over the counts alone, so that a file whose primitives add up to absurd sizes is
    // refused before anything is allocated (each accessor is fully validated later).
    std::size_t vertices = 0, triangles = 0;
    for (const tinygltf::Mesh& gm : m_.meshes)
        for (const tinygltf::Primitive& gp : gm.primitives) {
            const int mode = gp.mode < 0 ? TINYGLTF_MODE_TRIANGLES : gp.mode;
            if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN) continue;
            auto it = gp.attributes.find("POSITION");
            if (it == gp.attributes.end() || it->second < 0 || std::size_t(it->second) >= m_.accessors.size()) continue;
            const std::size_t n = std::min(m_.accessors[std::size_t(it->second)].count, kMaxVertices + 1);
            std::size_t nidx = n;
            if (gp.indices >= 0 && std::size_t(gp.indices) < m_.accessors.size())
                nidx = std::min(m_.accessors[std::size_t(gp.indices)].count, kMaxVertices + 1);
            vertices += n;
            triangles += mode == TINYGLTF_MODE_TRIANGLES ? nidx / 3 : (nidx >= 3 ? nidx - 2 : 0);
            if (vertices > kMaxVertices)
                fail("the triangle primitives hold more than " + std::to_string(kMaxVertices) + " vertices in total (limit)");
            if (triangles > kMaxTriangles)
                fail("more than " + std::to_string(kMaxTriangles) + " triangles in the file (limit)");
        }
    for (std::size_t mi = 0; mi < m_.meshes.size(); ++mi) {
        const tinygltf::Mesh& gm = m_.meshes[mi];
        Mesh mesh;
        mesh.name = gm.name.empty() ? "mesh_" + std::to_string(mi) : gm.name;
        for (std::size_t pi = 0; pi < gm.primitives.size(); ++pi) {
            Primitive p;
            const std::string where = "mesh " + std::to_string(mi) + " primitive " + std::to_string(pi);
            if (convert_primitive(gm.primitives[pi], where, p)) mesh.primitives.push_back(std::move(p));
        }
        scene_.meshes.push_back(std::move(mesh));
    }
}

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

}  // namespace

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

    Loader loader(path, model, options.texture_budget_bytes);
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
