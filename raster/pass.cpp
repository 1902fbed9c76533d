// raster/pass.cpp — LD06 raster passes (see pass.h): views fitted to the scene, the blurred
// depth test (LD06 eq. 1-4), blend modes, and the two traversals (plain per-triangle reference,
// tiled oneTBB), both calling the one per-fragment function `fragment`.
#include "raster/pass.h"

#include "raster/tiles.h"

#include <cmath>
#include <limits>
#include <unordered_map>

#include <glm/gtc/matrix_transform.hpp>

#include "raster/raster_internal.h"
#include "core/maths.h"

namespace aq::raster {

using namespace detail;

// LD06 eq. 3: scale 4 and bias (0, -1, -2, -3) per channel; 8-bit unsigned normalised storage
// rounds to the nearest of 255 steps (GL's float -> UNORM8 conversion); eq. 4 decodes the sum / 4.
namespace {
constexpr float kRgba8Scale = 4.0f;
constexpr float kUnorm8 = 255.0f;
}  // namespace

float quantize_depth_rgba8(float d) {
    d = maths::sat(d);
    float sum = 0.0f;
    for (int k = 0; k < 4; ++k) sum += std::nearbyint(maths::sat(kRgba8Scale * d - float(k)) * kUnorm8) / kUnorm8;
    return sum / kRgba8Scale;
}

PassScene make_pass_scene(const scene::Scene& sc, const scene::Camera& cam, int width, int height) {
    check_image_size(width, height, "raster pass output");
    PassScene ps;
    ps.scene = &sc;
    ps.camera = cam;
    ps.width = width;
    ps.height = height;
    ps.bounds = sc.world_bounds();
    if (!sc.strokes.empty()) ps.strokes = &sc.strokes;
    if (!ps.bounds.valid) throw Error("raster pass: the scene has no finite geometry");
    glm::vec3 d;
    if (!sc.lights.empty()) {
        d = sc.lights.front().direction;
    } else {
        // The G-buffer's key light is fixed in view space (raster/material.cpp); the same light.
        d = glm::transpose(glm::mat3(cam.view)) * default_view_light().dir;
    }
    const float len = glm::length(d);
    if (!(std::isfinite(len) && len > 0.0f)) throw Error("raster pass: the light direction is zero or not finite");
    ps.light_dir = d / len;
    return ps;
}

PassViewSetup pass_view(const PassScene& ps, PassView view, float scale) {
    if (!(scale >= 0.05f && scale <= 4.0f)) throw Error("raster pass: scale must be in [0.05, 4]");
    PassViewSetup v;
    const glm::vec3 lo = ps.bounds.min, hi = ps.bounds.max;
    if (view == PassView::Camera) {
        v.camera = ps.camera;
        // Every camera pass projects with the output's aspect, whatever its rounded size.
        if (!v.camera.aspect) v.camera.aspect = float(ps.width) / float(ps.height);
        v.width = std::max(1, int(std::lround(double(scale) * ps.width)));
        v.height = std::max(1, int(std::lround(double(scale) * ps.height)));
        float dmin = std::numeric_limits<float>::infinity(), dmax = -dmin;
        for (int k = 0; k < 8; ++k) {
            const glm::vec3 c((k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z);
            const float e = -(v.camera.view * glm::vec4(c, 1.0f)).z;
            dmin = std::min(dmin, e);
            dmax = std::max(dmax, e);
        }
        dmin = std::max(dmin, v.camera.znear);
        dmax = std::min(dmax, v.camera.zfar);
        if (!(dmax > dmin)) {
            dmin = v.camera.znear;
            dmax = v.camera.zfar;
        }
        v.depth_near = dmin;
        v.depth_far = dmax;
    } else {
        const glm::vec3 c = (lo + hi) * 0.5f;
        const float R = glm::length(hi - lo) * 0.5f;
        if (!(std::isfinite(R) && R > 0.0f) || !std::isfinite(c.x + c.y + c.z))
            throw Error("raster pass: zero-area light frustum (the scene has no extent)");
        const glm::vec3 d = ps.light_dir;
        const glm::vec3 up = std::abs(d.y) < 0.99f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
        scene::Camera cam;
        cam.name = "light";
        cam.view = glm::lookAt(c + d * (2.0f * R), c, up);
        cam.orthographic = true;
        cam.xmag = cam.ymag = R;
        cam.znear = R;
        cam.zfar = 3.0f * R;
        cam.aspect = 1.0f;
        v.camera = cam;
        v.width = v.height = std::max(1, int(std::lround(double(scale) * std::max(ps.width, ps.height))));
        v.depth_near = R;
        v.depth_far = 3.0f * R;
    }
    check_image_size(v.width, v.height, "raster pass");
    return v;
}

LightSample light_space(const PassViewSetup& light, glm::vec3 world, int map_w, int map_h) {
    const glm::vec4 p = light.camera.view * glm::vec4(world, 1.0f);
    const float nx = p.x / light.camera.xmag, ny = p.y / light.camera.ymag;
    // The rasterizer's NDC -> pixel mapping (raster/vertex.cpp snap_into), y down.
    return {(nx + 1.0f) * (0.5f * float(map_w)), (1.0f - ny) * (0.5f * float(map_h)), light.normalized(-p.z)};
}

namespace {

// Everything the per-fragment function reads, fixed for one pass.
struct PassContext {
    const TrianglePass* p = nullptr;
    PassViewSetup view;
    glm::vec3 light_view{0, 0, 1};  // unit light direction in the pass view's space
    glm::mat4 view_to_world{1.0f};
    PassViewSetup light;            // Shadow value: the light view the shadow map was rendered from
    View<const float> depth_map, shadow_map;
    const scene::LayerTable* layers = nullptr;
    //! LayerId, ObjectId with foliage_layer off: per draw of the frame, 1 = foliage (writes the
    //! background); empty = every draw writes its ID.
    std::vector<char> foliage_background;
    float background = 0.0f;
};

float sample_map(const View<const float>& m, float px, float py) {
    return maths::sample_bilinear(m, px, py, Border::Clamp);
}

// View-space position and normal of a fragment (the part of interpolate() the passes need), and
// whether it is a back face.
struct PosNormal {
    glm::vec3 pos, normal;
    bool back;
};
inline PosNormal gather(const Frame& fr, const Chunk& ch, const TriSetup& t, const Bary& b) {
    float o[3];
    original_weights(ch, t, b, o);
    const DrawVertices& dv = fr.draws[t.draw];
    const std::uint32_t* idx = t.v;
    const DrawVertices::Shading& v0 = dv.view[idx[0]];
    const DrawVertices::Shading& v1 = dv.view[idx[1]];
    const DrawVertices::Shading& v2 = dv.view[idx[2]];
    return {v0.pos + (v1.pos - v0.pos) * o[1] + (v2.pos - v0.pos) * o[2],
            v0.normal + (v1.normal - v0.normal) * o[1] + (v2.normal - v0.normal) * o[2], t.back()};
}

// PassValue::Depth of a fragment at linear eye depth d.
inline float depth_value(const PassContext& cx, float d) { return maths::sat(cx.view.normalized(d)); }

// The value a fragment writes (PassValue), given its weights.
inline float fragment_value(const PassContext& cx, const Frame& fr, const Chunk& ch, const TriSetup& t, const Bary& b) {
    const TrianglePass& p = *cx.p;
    switch (p.value) {
        case PassValue::Depth: return depth_value(cx, b.depth);
        case PassValue::Coverage: return 1.0f;
        case PassValue::Lighting: {
            const PosNormal g = gather(fr, ch, t, b);
            glm::vec3 n = g.normal;
            const float l2 = glm::dot(n, n);
            n = l2 > 0.0f ? n * (1.0f / std::sqrt(l2)) : glm::vec3(0, 0, 1);
            if (g.back) n = -n;  // two-sided lighting, as gl_FrontFacing
            return maths::sat((1.0f + glm::dot(n, cx.light_view)) * 0.5f);
        }
        case PassValue::Shadow: {
            const PosNormal g = gather(fr, ch, t, b);
            const glm::vec3 w = glm::vec3(cx.view_to_world * glm::vec4(g.pos, 1.0f));
            const LightSample ls = light_space(cx.light, w, cx.shadow_map.width, cx.shadow_map.height);
            float D = sample_map(cx.shadow_map, ls.x, ls.y);
            if (p.shadow_test == DepthTest::BlurredRgba8) D = quantize_depth_rgba8(D);
            const float delta = p.shadow_test == DepthTest::Binary ? 0.0f : p.shadow_delta;
            return 1.0f - blurred_visibility(D, ls.depth, delta, p.shadow_beta);
        }
        case PassValue::IntensityTexture: {
            const scene::Material& m = *fr.draws[t.draw].mat;
            const scene::Texture* tex = texture_of(fr.ctx, m.intensity_texture);
            if (!tex) return 0.0f;
            const FragmentInput in = interpolate(fr, ch, t, b);
            if (!in.has_uv) return 0.0f;
            return sample_texture(*tex, m.intensity_texture.sampler, in.uv, in.uv_grad)[p.channel];
        }
        case PassValue::LayerId: {
            const DrawVertices& dv = fr.draws[t.draw];
            if (!cx.foliage_background.empty() && cx.foliage_background[t.draw]) return 0.0f;
            return float(cx.layers->of(dv.object_id, dv.prim->material) + 1);
        }
        case PassValue::ObjectId: {
            if (!cx.foliage_background.empty() && cx.foliage_background[t.draw]) return 0.0f;
            return float(fr.draws[t.draw].object_id);
        }
    }
    return 0.0f;
}

// The one per-fragment function (both traversals): test, value, blend into *dst; z is the
// pixel's depth-buffer entry (Binary test only).
inline void fragment(const PassContext& cx, const Frame& fr, const Chunk& ch, const TriSetup& t,
                     const std::int64_t e[3], int x, int y, float* dst, float* z) {
    const TrianglePass& p = *cx.p;
    const Bary b = perspective_bary(t, e);
    float fv = 1.0f;
    if (p.test == DepthTest::Binary) {
        if (!(b.depth < *z)) return;
        if (needs_alpha_test(fr, t) && !alpha_pass(fr, ch, t, b)) return;
        *z = b.depth;
    } else {
        if (needs_alpha_test(fr, t) && !alpha_pass(fr, ch, t, b)) return;
        float D = sample_map(cx.depth_map, maths::texel_coord(x, cx.view.width, cx.depth_map.width),
                             maths::texel_coord(y, cx.view.height, cx.depth_map.height));
        if (p.test == DepthTest::BlurredRgba8) D = quantize_depth_rgba8(D);
        fv = blurred_visibility(D, cx.view.normalized(b.depth), p.delta, p.beta);
    }
    const float v = fragment_value(cx, fr, ch, t, b);
    switch (p.blend) {
        case Blend::Replace: *dst = fv * v; break;
        case Blend::Add: *dst = maths::sat(*dst + fv * v); break;
        case Blend::Over: {
            const float a = fv * p.alpha;
            *dst = v * a + *dst * (1.0f - a);
            break;
        }
    }
}

void check_pass(const TrianglePass& p) {
    auto finite_in = [](float v, float lo, float hi) { return std::isfinite(v) && v >= lo && v <= hi; };
    if (!finite_in(p.delta, 0, 1) || !finite_in(p.shadow_delta, 0, 1))
        throw Error("raster pass: delta must be in [0, 1]");
    if (!finite_in(p.beta, -1, 1) || !finite_in(p.shadow_beta, -1, 1))
        throw Error("raster pass: beta must be in [-1, 1]");
    if (!finite_in(p.alpha, 0, 1)) throw Error("raster pass: alpha must be in [0, 1]");
    if (!finite_in(p.lighting_background, 0, 1)) throw Error("raster pass: lighting background must be in [0, 1]");
    if (p.test != DepthTest::Binary && (!p.depth_map || p.depth_map->empty() || p.depth_map->channels() != 1))
        throw Error("raster pass: the blurred depth test needs a 1-channel depth map");
    if (p.channel < 0 || p.channel > 2) throw Error("raster pass: channel must be 0, 1 or 2");
    if (p.value == PassValue::Shadow && (!p.shadow_map || p.shadow_map->empty() || p.shadow_map->channels() != 1))
        throw Error("raster pass: the shadow value needs a 1-channel light-view depth map");
}

}  // namespace

struct PassFrameCache::Entry {
    PassView view;
    float scale;
    DrawSet draw;
    bool fast;
    int threads;
    glm::mat4 camera_view;
    int width, height;
    std::unique_ptr<RenderSettings> rs;  // the Frame keeps it by pointer
    Frame frame;
    bool prepared = false;
    //! The visible fragment of every pixel (W x H, row-major; chunk kNoChunk = none) as the deferred
    //! passes (binary test, replace) resolve it: it depends on the prepared frame alone, not on what
    //! the pass writes, so the first such pass stores it and the others of this view read it
    //! (LD06's depth, shadow, lighting and layer-ID passes resolve the camera view once).
    std::vector<TileRef> winners;
    bool resolved = false;
};

PassFrameCache::PassFrameCache() = default;
PassFrameCache::~PassFrameCache() = default;

namespace {

//! What every fragment of pass p reads: the view, light, maps, background and layer table
//! (own_layers holds the drawn scene's own table when the job gave none).
void init_context(PassContext& cx, const PassScene& ps, const TrianglePass& p, scene::LayerTable& own_layers) {
    cx.p = &p;
    cx.view = pass_view(ps, p.view, p.scale);
    cx.light_view = glm::normalize(glm::mat3(cx.view.camera.view) * ps.light_dir);
    cx.view_to_world = glm::inverse(cx.view.camera.view);
    if (p.depth_map && !p.depth_map->empty() && p.depth_map->channels() == 1) cx.depth_map = p.depth_map->view<float>();
    if (p.value == PassValue::Shadow) {
        cx.light = pass_view(ps, PassView::Light, 1.0f);
        cx.shadow_map = p.shadow_map->view<float>();
    }
    cx.background = p.value == PassValue::Depth ? 1.0f : p.value == PassValue::Lighting ? p.lighting_background : 0.0f;
    // Without the job's table (tests, callers of the typed API): the drawn scene's own layers.
    cx.layers = ps.layers;
    if (p.value == PassValue::LayerId && !cx.layers) {
        own_layers = scene::build_layer_table(*ps.scene);
        cx.layers = &own_layers;
    }
}

//! The prepared frame of pass p: this frame's shared one for the same view, size and draw set
//! (ps.frames), or a new one — kept in the cache when there is one, else in `own`.
PassFrameCache::Entry& pass_frame(const PassScene& ps, const TrianglePass& p, const PassContext& cx, const Exec& ex,
                                  std::unique_ptr<PassFrameCache::Entry>& own) {
    const bool fast = ex.traversal == Traversal::Fast;
    const int W = cx.view.width, H = cx.view.height;
    if (ps.frames)
        for (auto& e : ps.frames->entries)
            if (e->view == p.view && e->scale == p.scale && e->draw == p.draw && e->fast == fast && e->threads == ex.threads &&
                e->camera_view == cx.view.camera.view && e->width == W && e->height == H)
                return *e;
    own = std::make_unique<PassFrameCache::Entry>();
    own->view = p.view;
    own->scale = p.scale;
    own->draw = p.draw;
    own->fast = fast;
    own->threads = ex.threads;
    own->camera_view = cx.view.camera.view;
    own->width = W;
    own->height = H;
    own->rs = std::make_unique<RenderSettings>();
    RenderSettings& rs = *own->rs;
    rs.width = W;
    rs.height = H;
    rs.exec = ex;
    rs.tremor.enabled = false;  // passes draw without tremor or bleeding displacement (LD06 has neither)
    rs.bleed_displacement = false;
    own->frame = make_frame(*ps.scene, cx.view.camera, rs, W, H);
    PassFrameCache::Entry& e = *own;
    if (ps.frames) ps.frames->entries.push_back(std::move(own));
    return e;
}

//! LayerId and ObjectId with foliage_layer off: which draws of the frame are foliage (they write
//! the background).
void mark_foliage_background(PassContext& cx, const scene::Scene& sc, const Frame& fr) {
    std::unordered_map<std::uint32_t, const scene::Instance*> by_id;
    for (const scene::Instance& inst : sc.instances) by_id.emplace(inst.object_id, &inst);
    cx.foliage_background.assign(fr.draws.size(), 0);
    for (std::size_t d = 0; d < fr.draws.size(); ++d)
        if (const auto it = by_id.find(fr.draws[d].object_id); it != by_id.end())
            cx.foliage_background[d] = scene::is_foliage(sc, *it->second, *fr.draws[d].prim);
}

//! One tile of a deferred pass (binary test, replace): visibility first — resolved here, or read
//! from the frame's shared winners when an earlier pass resolved it — then each pixel's winner
//! computed once (the fragment the forward loop writes last: the first of the nearest).
void deferred_tile(const PassContext& cx, const Frame& fr, PassFrameCache::Entry& entry, bool resolved, int tile,
                   const TileRect& tr, float* img) {
    const int W = cx.view.width;
    const int X0 = tr.x0, Y0 = tr.y0, X1 = tr.x1, Y1 = tr.y1;
    float zbuf[kTile * kTile];
    std::fill_n(zbuf, kTile * kTile, std::numeric_limits<float>::infinity());
    TileRef win[kTile * kTile];
    if (resolved) {
        for (int y = Y0; y <= Y1; ++y)
            std::copy_n(entry.winners.data() + std::size_t(y) * W + X0, X1 - X0 + 1, win + (y - Y0) * kTile);
    } else {
        for (TileRef& r : win) r.chunk = kNoChunk;
        resolve_tile(fr, tile, X0, Y0, X1, Y1, zbuf, win);
        if (!entry.winners.empty())
            for (int y = Y0; y <= Y1; ++y)  // this tile's rows of the shared visibility
                std::copy_n(win + (y - Y0) * kTile, X1 - X0 + 1, entry.winners.data() + std::size_t(y) * W + X0);
    }
    if (!resolved && cx.p->value == PassValue::Depth) {
        // The value is the winner's depth, which the resolve just computed (the same
        // perspective_bary): normalised straight from the tile's depth buffer.
        for (int y = Y0; y <= Y1; ++y)
            for (int x = X0; x <= X1; ++x) {
                const int li = (y - Y0) * kTile + (x - X0);
                if (win[li].chunk != kNoChunk) img[std::size_t(y) * W + x] = depth_value(cx, zbuf[li]);
            }
        return;
    }
    for (int y = Y0; y <= Y1; ++y)
        for (int x = X0; x <= X1; ++x) {
            const TileRef r = win[(y - Y0) * kTile + (x - X0)];
            if (r.chunk == kNoChunk) continue;
            const Chunk& ch = fr.chunks[r.chunk];
            const TriSetup& t = ch.tris[r.tri];
            std::int64_t e[3];
            edge_values(t, x, y, e);
            img[std::size_t(y) * W + x] = fragment_value(cx, fr, ch, t, perspective_bary(t, e));
        }
}

//! One tile of a forward pass: its binned triangles in submission order, every fragment through
//! `fragment` (test, value, blend).
void forward_tile(const PassContext& cx, const Frame& fr, int tile, const TileRect& tr, float* img) {
    const int W = cx.view.width;
    const int X0 = tr.x0, Y0 = tr.y0, X1 = tr.x1, Y1 = tr.y1;
    float zbuf[kTile * kTile];
    std::fill_n(zbuf, kTile * kTile, std::numeric_limits<float>::infinity());
    for (const Chunk& ch : fr.chunks)
        for (std::uint32_t k = ch.bin_offsets[tile]; k < ch.bin_offsets[tile + 1]; ++k) {
            const TriSetup& t = ch.tris[ch.bin_items[k]];
            for_each_inside(t, std::max<int>(t.x0, X0), std::min<int>(t.x1, X1), std::max<int>(t.y0, Y0), std::min<int>(t.y1, Y1),
                            [&](int x, int y, const std::int64_t* e) {
                                fragment(cx, fr, ch, t, e, x, y, img + std::size_t(y) * W + x, &zbuf[(y - Y0) * kTile + (x - X0)]);
                            });
        }
}

}  // namespace

void render_triangle_pass(ImageF& out, const PassScene& ps, const TrianglePass& p, const Exec& ex,
                          std::vector<std::string>* warnings) {
    if (!ps.scene) throw Error("raster pass: no scene");
    check_pass(p);
    std::vector<std::string> local;
    if (!warnings) warnings = &local;
    PassContext cx;
    scene::LayerTable own_layers;
    init_context(cx, ps, p, own_layers);
    const int W = cx.view.width, H = cx.view.height;
    // Passes draw without culling; `draw` chooses the instances.
    const scene::Scene& sc = *ps.scene;
    const DrawSet draw = p.draw;
    const DrawFilter filter = [&sc, draw](const scene::Instance& inst, const scene::Primitive& prim) {
        if (draw == DrawSet::All) return true;
        return scene::is_foliage(sc, inst, prim) == (draw == DrawSet::Foliage);
    };
    const bool fast = ex.traversal == Traversal::Fast;
    std::unique_ptr<PassFrameCache::Entry> own;
    PassFrameCache::Entry* entry = &pass_frame(ps, p, cx, ex, own);
    Frame& fr = entry->frame;
    if (out.width() != W || out.height() != H || out.channels() != 1) out = ImageF(W, H, 1, cx.background);
    else std::fill(out.data(), out.data() + std::size_t(W) * H, cx.background);
    float* const img = out.data();
    PhaseTimer timer;
    const bool deferred = p.test == DepthTest::Binary && p.blend == Blend::Replace;
    const bool resolved = entry->resolved;  // the visibility of an earlier deferred pass of this frame
    // Kept only where later passes can read it (a frame cache).
    if (fast && deferred && !resolved && ps.frames) entry->winners.resize(std::size_t(W) * H);
    auto body = [&] {
        if (!entry->prepared) {
            prepare(fr, sc, cx.view.camera, fast, fast, warnings, timer, &filter);
            entry->prepared = true;
        }
        if (!p.foliage_layer && (p.value == PassValue::LayerId || p.value == PassValue::ObjectId)) mark_foliage_background(cx, sc, fr);
        auto reference = [&] {
            std::vector<float> zbuf(std::size_t(W) * H, std::numeric_limits<float>::infinity());
            for_each_reference_fragment(fr, [&](const Chunk& ch, const TriSetup& t, int x, int y, const std::int64_t* e) {
                const std::size_t i = std::size_t(y) * W + x;
                fragment(cx, fr, ch, t, e, x, y, img + i, &zbuf[i]);
            });
        };
        traverse_tiles(ex, fr.grid, reference, [&](int tile, TileRect tr) {
            if (deferred) deferred_tile(cx, fr, *entry, resolved, tile, tr, img);
            else forward_tile(cx, fr, tile, tr, img);
        });
    };
    if (fast) with_arena(ex, body);
    else body();
    if (fast && deferred && ps.frames) entry->resolved = true;
    if (fr.draws.empty())
        warnings->push_back(std::string("raster pass draws nothing: no ") +
                            (p.draw == DrawSet::Foliage ? "foliage" : p.draw == DrawSet::NonFoliage ? "non-foliage geometry" : "geometry") +
                            " in the scene (docs/ld06.md \"Foliage\")");
}

}  // namespace aq::raster
