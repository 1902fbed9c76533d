// scenes/gltf_materials.cpp — the glTF reader's materials and textures (images decoded by
// OpenImageIO within the decode budget; scenes/gltf_reader.h).
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


namespace aq::scene::gltf {

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

}  // namespace aq::scene::gltf
