// scenes/scene.cpp — scene-wide queries.
// -fno-trapping-math (FP exception flags only, no value changes) lets GCC vectorise the texture
// code loops' compares and selects, as in the stylize stages.
#pragma GCC optimize("no-trapping-math")
#include "scenes/scene.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/color.h"

namespace aq::scene {

Bounds Scene::world_bounds() const {
    Bounds b;
    for (const Instance& inst : instances) {
        if (inst.mesh < 0 || inst.mesh >= int(meshes.size())) continue;
        for (const Primitive& p : meshes[inst.mesh].primitives)
            for (const glm::vec3& v : p.positions) {
                const glm::vec4 w = inst.world * glm::vec4(v, 1.0f);
                if (!std::isfinite(w.x) || !std::isfinite(w.y) || !std::isfinite(w.z)) continue;
                const glm::vec3 q(w);
                if (!b.valid) {
                    b.min = b.max = q;
                    b.valid = true;
                } else {
                    b.min = glm::min(b.min, q);
                    b.max = glm::max(b.max, q);
                }
            }
    }
    return b;
}

std::size_t Scene::triangle_count() const {
    std::size_t n = 0;
    for (const Instance& inst : instances)
        if (inst.mesh >= 0 && inst.mesh < int(meshes.size()))
            for (const Primitive& p : meshes[inst.mesh].primitives) n += p.indices.size() / 3;
    return n;
}

namespace {
//! The image channel lane L of a texel reads (raster/material.cpp texel()), or -1 for a constant.
int lane_source(int channels, int lane) {
    if (channels == 1) return lane < 3 ? 0 : -1;
    if (channels == 2) return lane < 2 ? lane : -1;
    if (channels == 3) return lane < 3 ? lane : -1;
    return lane;
}
constexpr float kLaneConstant[4] = {0.0f, 0.0f, 0.0f, 1.0f};  // missing G/B: 0, missing alpha: 1
}  // namespace

TextureCodes texture_codes(const ImageF& decoded) {
    TextureCodes c;
    const int nc = decoded.channels();
    if (decoded.empty() || nc < 1 || nc > 4) return c;
    const std::size_t n = std::size_t(decoded.width()) * std::size_t(decoded.height());
    const std::size_t nv = n * std::size_t(nc);
    // Every value's code, in one flat loop (vectorised): round(v * 255) for v in [0, 1]; any
    // other value (NaN included) leaves no codes. Then widened to four lanes per texel.
    UninitializedVector<std::uint8_t> flat(nv);
    const float* d = decoded.data();
    int bad = 0;
    for (std::size_t j = 0; j < nv; ++j) {
        const float v = d[j];
        bad |= int(v < 0.0f) | int(v > 1.0f) | int(v != v);
        const float vc = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f;  // NaN -> 0: a defined conversion
        flat[j] = std::uint8_t(int(vc * 255.0f + 0.5f));
    }
    if (bad) return c;
    c.width = decoded.width();
    c.height = decoded.height();
    if (nc == 4) {
        c.codes = std::move(flat);
        return c;
    }
    c.codes.assign(4 * n, 0);
    for (int lane = 0; lane < 4; ++lane)
        if (const int src = lane_source(nc, lane); src >= 0)
            for (std::size_t i = 0; i < n; ++i) c.codes[4 * i + std::size_t(lane)] = flat[i * std::size_t(nc) + std::size_t(src)];
    return c;
}

void texture_codes_finish(TextureCodes& c, const ImageF& img) {
    const int nc = img.channels();
    const std::size_t n = std::size_t(img.width()) * std::size_t(img.height());
    if (c.empty() || c.codes.size() != 4 * n || nc < 1 || nc > 4) {
        c = TextureCodes{};
        return;
    }
    // tab[lane][code]: the bits of the first value with that code; every value must equal its
    // entry. kUnset (unused codes) is a NaN pattern: a value with those bits leaves no codes.
    constexpr std::uint32_t kUnset = 0xFFFFFFFFu;
    std::array<std::uint32_t, 4 * 256> tab;
    tab.fill(kUnset);
    const float* d = img.data();
    const std::uint8_t* k = c.codes.data();
    bool ok = true;
    for (int lane = 0; lane < 4; ++lane) {
        const int src = lane_source(nc, lane);
        std::uint32_t* t = tab.data() + 256 * lane;
        if (src < 0) {  // a constant lane (its codes are all 0): every entry the constant
            std::uint32_t b;
            std::memcpy(&b, &kLaneConstant[lane], sizeof b);
            std::fill_n(t, 256, b);
            continue;
        }
        // The first value of each code (written last, going backwards), then every value
        // compared with its code's entry (branch-free).
        for (std::size_t i = n; i-- > 0;) std::memcpy(&t[k[4 * i + std::size_t(lane)]], &d[i * std::size_t(nc) + std::size_t(src)], sizeof(float));
        std::uint32_t diff = 0;
        for (std::size_t i = 0; i < n; ++i) {
            std::uint32_t b;
            std::memcpy(&b, &d[i * std::size_t(nc) + std::size_t(src)], sizeof b);
            diff |= (t[k[4 * i + std::size_t(lane)]] ^ b) | std::uint32_t(b == kUnset);
        }
        ok = ok && diff == 0;
    }
    if (!ok) {
        c = TextureCodes{};
        return;
    }
    for (int lane = 0; lane < 4; ++lane)
        for (int q = 0; q < 256; ++q) std::memcpy(&c.lut[std::size_t(lane)][std::size_t(q)], &tab[std::size_t(256 * lane + q)], sizeof(float));
}

namespace {
//! The taps of destination texel i of a mip level of n texels (texture_mip_level): index of the
//! first source texel, count (1-3) and weights.
struct MipTaps {
    int first, count;
    float w[3];
};
MipTaps mip_taps(int n, int i) {
    if (n == 1) return {0, 1, {1.0f, 0.0f, 0.0f}};
    if (n % 2 == 0) return {2 * i, 2, {0.5f, 0.5f, 0.0f}};
    const int m = n / 2;
    const float inv = 1.0f / float(n);
    return {2 * i, 3, {float(m - i) * inv, float(m) * inv, float(i + 1) * inv}};
}
}  // namespace

namespace {
// Mip levels are built row by row from a row source: an object with width(), height(),
// channels() and row(y), the values of source row y (valid until its next call): a float image,
// 8-bit codes (each row expanded through the tables), or MipRows of another source (the rows of
// the level below it, computed on demand: level 2 from level 0 without storing level 1). A source
// is copied per task (its scratch rows are its own).

//! Rows of a float image.
struct ImageRows {
    const ImageF* img;
    int width() const { return img->width(); }
    int height() const { return img->height(); }
    int channels() const { return img->channels(); }
    const float* row(int y) { return img->data() + std::size_t(y) * std::size_t(width()) * std::size_t(channels()); }
};

//! Rows of 8-bit codes, expanded through the tables (RGBA).
struct CodeRows {
    const TextureCodes* codes;
    std::vector<float> buf = std::vector<float>(std::size_t(codes->width) * 4);
    int width() const { return codes->width; }
    int height() const { return codes->height; }
    int channels() const { return 4; }
    const float* row(int y) {
        const std::uint8_t* k = codes->codes.data() + std::size_t(y) * std::size_t(codes->width) * 4;
        for (std::size_t i = 0; i < buf.size(); i += 4)
            for (std::size_t lane = 0; lane < 4; ++lane) buf[i + lane] = codes->lut[lane][k[i + lane]];
        return buf.data();
    }
};

//! The next mip level of `Src`, row by row: for output row y, its source rows reduced along x (taps in
//! order), then those rows combined along y (taps in order) — the same sums, in the same order,
//! as reducing every row first and then the columns (the definition in scene.h).
template <class Src>
struct MipRows {
    Src src;
    int w2 = std::max(1, src.width() / 2), h2 = std::max(1, src.height() / 2), nc = src.channels();
    std::vector<MipTaps> xt = x_taps(src.width(), w2);
    std::vector<float> reduced = std::vector<float>(3 * row_values());
    std::vector<float> out = std::vector<float>(row_values());

    static std::vector<MipTaps> x_taps(int w, int w2) {
        std::vector<MipTaps> t(std::size_t(w2), MipTaps{});
        for (int x = 0; x < w2; ++x) t[std::size_t(x)] = mip_taps(w, x);
        return t;
    }
    std::size_t row_values() const { return std::size_t(w2) * std::size_t(nc); }
    // As a row source itself (a level built from the level two above, finish_texture).
    int width() const { return w2; }
    int height() const { return h2; }
    int channels() const { return nc; }
    const float* row(int y) {
        row_into(y, out.data());
        return out.data();
    }
    //! Output row y into dst (row_values() floats).
    void row_into(int y, float* dst) {
        const std::size_t row2 = row_values();
        const MipTaps t = mip_taps(src.height(), y);
        // Even width and height (every tap pair weighs 0.5): the same operations in the same order
        // as the general loops below, written so that the compiler vectorises them (a 4096^2 map's
        // level 1 in about a third of the time).
        const bool pairs_x = src.width() % 2 == 0, pairs_y = t.count == 2 && src.height() % 2 == 0;
        for (int k = 0; k < t.count; ++k) {
            const float* in = src.row(t.first + k);
            float* r = reduced.data() + std::size_t(k) * row2;
            if (pairs_x && nc == 4) {
                for (std::size_t x = 0; x < std::size_t(w2); ++x)
                    for (std::size_t c = 0; c < 4; ++c)
                        r[4 * x + c] = (0.0f + 0.5f * in[8 * x + c]) + 0.5f * in[8 * x + 4 + c];
                continue;
            }
            for (int x = 0; x < w2; ++x) {
                const MipTaps& tx = xt[std::size_t(x)];
                for (int c = 0; c < nc; ++c) {
                    float sum = 0.0f;
                    for (int q = 0; q < tx.count; ++q) sum += tx.w[q] * in[std::size_t(tx.first + q) * std::size_t(nc) + std::size_t(c)];
                    r[std::size_t(x) * std::size_t(nc) + std::size_t(c)] = sum;
                }
            }
        }
        if (pairs_y) {
            const float* r0 = reduced.data();
            const float* r1 = reduced.data() + row2;
            for (std::size_t j = 0; j < row2; ++j) dst[j] = (0.0f + 0.5f * r0[j]) + 0.5f * r1[j];
            return;
        }
        for (std::size_t j = 0; j < row2; ++j) {
            float sum = 0.0f;
            for (int k = 0; k < t.count; ++k) sum += t.w[k] * reduced[std::size_t(k) * row2 + j];
            dst[j] = sum;
        }
    }
};

//! The next mip level of `src`, every row of it, rows in parallel (each written by one task, each
//! task with its own copy of the source): the same bits on any thread count.
template <class Src>
ImageF build_level(const Src& src) {
    const MipRows<Src> proto{src};
    ImageF out(proto.w2, proto.h2, proto.nc, kUninitialized);
    tbb::parallel_for(tbb::blocked_range<int>(0, proto.h2, 16), [&](const tbb::blocked_range<int>& r) {
        MipRows<Src> rows = proto;
        for (int y = r.begin(); y < r.end(); ++y) rows.row_into(y, out.data() + std::size_t(y) * rows.row_values());
    });
    return out;
}
}  // namespace

ImageF texture_mip_level(const ImageF& level) { return build_level(ImageRows{&level}); }

ImageF texture_mip_level(const TextureCodes& level) { return build_level(CodeRows{&level}); }

float TexelMap::operator()(float v, int lane) const {
    switch (kind) {
        case Kind::Srgb: return lane < 3 ? srgb_to_linear(v) : v;
        case Kind::Control: return (v * scale + bias + 1.0f) * 0.5f;
        default: return v;
    }
}

glm::vec4 Texture::texel0(int x, int y) const {
    if (!codes.empty()) return codes.texel(x, y);
    const int nc = image.channels();
    glm::vec4 t;
    for (int lane = 0; lane < 4; ++lane) {
        const int src = lane_source(nc, lane);
        t[lane] = src < 0 ? kLaneConstant[lane] : image.at(x, y, src);
    }
    return t;
}

glm::vec4 Texture::level1_texel(int x, int y) const {
    // MipRows::row_into for one texel: each source row's taps along x, then the rows' taps along
    // y, every sum from 0 in tap order.
    const MipTaps ty = mip_taps(height(), y), tx = mip_taps(width(), x);
    glm::vec4 r[3];
    for (int k = 0; k < ty.count; ++k) {
        glm::vec4 sum(0.0f);
        for (int q = 0; q < tx.count; ++q) sum += tx.w[q] * texel0(tx.first + q, ty.first + k);
        r[k] = sum;
    }
    glm::vec4 v(0.0f);
    for (int k = 0; k < ty.count; ++k) v += ty.w[k] * r[k];
    return v;
}

std::vector<ImageF> Texture::all_mips() const {
    std::vector<ImageF> all = mips;
    if (level1_computed) all[0] = codes.empty() ? texture_mip_level(image) : texture_mip_level(codes);
    return all;
}

ImageF Texture::level0() const {
    if (codes.empty() && image.channels() == 4) return image;
    ImageF out(width(), height(), 4, kUninitialized);
    for (int y = 0; y < out.height(); ++y)
        for (int x = 0; x < out.width(); ++x) {
            const glm::vec4 t = texel0(x, y);
            for (int c = 0; c < 4; ++c) out.at(x, y, c) = t[c];
        }
    return out;
}

namespace {
//! A colour texture with some texel less than opaque: its levels average colour weighted by alpha.
bool has_coverage_alpha(const Texture& t) {
    if (!t.srgb) return false;
    if (!t.codes.empty()) {
        const std::uint8_t* k = t.codes.codes.data();
        const auto& alpha = t.codes.lut[3];
        for (std::size_t i = 3, n = t.codes.codes.size(); i < n; i += 4)
            if (alpha[k[i]] != 1.0f) return true;
        return false;
    }
    if (t.image.channels() != 4) return false;
    const float* p = t.image.data();
    for (std::size_t i = 0, n = t.image.num_values(); i < n; i += 4)
        if (p[i + 3] != 1.0f) return true;
    return false;
}
}  // namespace

void finish_texture(Texture& t) {
    t.mips.clear();
    t.level1_computed = false;
    if (t.empty() || (t.width() == 1 && t.height() == 1)) return;
    const bool coverage = has_coverage_alpha(t);
    const int w1 = std::max(1, t.width() / 2), h1 = std::max(1, t.height() / 2);
    const bool rgba = !t.codes.empty() || t.image.channels() == 4;
    if (!coverage && rgba && (w1 > 1 || h1 > 1) &&
        std::size_t(w1) * std::size_t(h1) * 4 * sizeof(float) >= kComputedLevel1Bytes) {
        // Level 1 computed where sampled (Texture::level1_texel); level 2 straight from level 0.
        t.level1_computed = true;
        t.mips.emplace_back();
        t.mips.push_back(t.codes.empty() ? build_level(MipRows<ImageRows>{ImageRows{&t.image}})
                                         : build_level(MipRows<CodeRows>{CodeRows{&t.codes}}));
    } else {
        t.mips.push_back(t.codes.empty() ? texture_mip_level(t.image) : texture_mip_level(t.codes));
    }
    while (t.mips.back().width() > 1 || t.mips.back().height() > 1) t.mips.push_back(texture_mip_level(t.mips.back()));
    if (!coverage) return;
    // Straight alpha (glTF): the colour of a level is the alpha-weighted average, the average of the
    // premultiplied colours divided by the average alpha, so the colour of transparent texels
    // (often white or black in leaf atlases) does not bleed into the leaves' colour as they shrink.
    // Where no texel of the footprint has alpha, the plain average (the level as built above).
    ImageF pre = t.level0();
    float* q = pre.data();
    for (std::size_t i = 0, n = pre.num_values(); i < n; i += 4)
        for (int c = 0; c < 3; ++c) q[i + c] *= q[i + 3];
    for (ImageF& lv : t.mips) {
        pre = texture_mip_level(pre);
        const float* p = pre.data();
        float* d = lv.data();
        for (std::size_t i = 0, n = lv.num_values(); i < n; i += 4)
            if (p[i + 3] > 0.0f)
                for (int c = 0; c < 3; ++c) d[i + c] = p[i + c] / p[i + 3];
    }
}

namespace {
bool names_foliage(std::string n) {
    for (char& c : n) c = char(std::tolower(static_cast<unsigned char>(c)));
    for (const char* w : {"foliage", "leaf", "leaves"})
        if (n.find(w) != std::string::npos) return true;
    return false;
}
}  // namespace

void FoliageSelection::add(std::vector<std::string>& list, const std::string& name) {
    const auto it = std::lower_bound(list.begin(), list.end(), name);
    if (it == list.end() || *it != name) list.insert(it, name);
}

DecodeBudget render_decode_budget(std::size_t bytes) {
    return {bytes, "the images one render decodes (the model's textures, the scene file's intensity and control textures: " +
                       std::to_string(bytes) + " bytes as RGBA float; docs/limits.md)"};
}

bool is_foliage(const Scene& sc, const Instance& inst, const Primitive& prim) {
    const Material* m = prim.material >= 0 && prim.material < int(sc.materials.size()) ? &sc.materials[prim.material] : nullptr;
    if (sc.foliage.set) {
        auto listed = [](const std::vector<std::string>& v, const std::string& n) {
            return std::binary_search(v.begin(), v.end(), n);  // sorted: FoliageSelection
        };
        const Mesh* mesh = inst.mesh >= 0 && inst.mesh < int(sc.meshes.size()) ? &sc.meshes[std::size_t(inst.mesh)] : nullptr;
        return listed(sc.foliage.nodes, inst.name) || (mesh && listed(sc.foliage.meshes, mesh->name)) ||
               (m && listed(sc.foliage.materials, m->name));
    }
    if (m && (m->alpha_mode == AlphaMode::Mask || names_foliage(m->name))) return true;
    if (inst.mesh >= 0 && inst.mesh < int(sc.meshes.size()) && names_foliage(sc.meshes[inst.mesh].name)) return true;
    return names_foliage(inst.name);
}

}  // namespace aq::scene
