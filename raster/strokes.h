// raster/strokes.h — LD06 §4.4 line strokes (Luft & Deussen 2006): 3D polylines drawn last, in
// creation order (painter's algorithm), with the blurred depth test's f_v as transparency, faded
// with distance, by n·v of the surface they belong to and, for hatching strokes, by n·l.
// Automatic contour strokes: the silhouette edges of non-foliage meshes chained into polylines.
// docs/ld06.md "Strokes".
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/exec.h"
#include "core/image.h"
#include "raster/pass.h"

namespace aq::raster {

//! Bounds of one strokes pass (refused before drawing): polylines, vertices in all, width.
inline constexpr std::size_t kMaxStrokes = 1'000'000;
inline constexpr std::size_t kMaxStrokeVertices = 4'000'000;
inline constexpr float kMaxStrokeWidthPx = 64.0f;
//! Work budget of one strokes pass, in pixel-segment distance tests, checked after projection and
//! before drawing (docs/limits.md "Work budgets"). Measured on our 2-core machines: a 20,000-point
//! stroke zig-zagging over a 720 x 720 image is 2.2e9 tests, drawn in 0.95 s on 2 threads, so the
//! budget caps a pass at about 4.5 s there (9 s on one thread). Hand-drawn and contour strokes are
//! short segments: 1,000,000 points of them are about 1e8 tests.
inline constexpr std::uint64_t kMaxStrokeWork = 10'000'000'000ull;
//! Stroke widths are given in pixels at a 720-pixel-wide raster (LD06's output) and scaled.
inline constexpr int kLd06SizeReferenceStrokes = 720;

//! Triangles (and welded edges) per task of contour extraction's facing and silhouette tests.
inline constexpr std::size_t kContourBlock = 1024;

//! A stroke is the scene's (scenes/scene.h): points, optional normals, hatching flag.
using Stroke = scene::Stroke;

struct StrokeParams {
    float width_px = 2.0f;      //!< line width in pixels at 720 px (scaled with the raster width), (0, 64]
    float scale = 1.0f;         //!< raster size as a scale of the output size
    DepthTest test = DepthTest::Blurred;
    float delta = 0.02f, beta = 0.02f;  //!< eq. 2 (ours: a narrow band; β = δ keeps strokes on their surface)
    float fade_near = 0.6f, fade_far = 1.0f;  //!< distance fade over normalised depth: 1 before near, 0 at far
    float nv_lo = 0.05f, nv_hi = 0.3f;        //!< n·v fade: 0 at |n·v| <= lo, 1 at >= hi
    float nl_lo = -0.2f, nl_hi = 0.4f;        //!< hatching: 1 at n·l <= lo, 0 at >= hi (lit side fades)
    float alpha = 1.0f;         //!< stroke opacity
    const ImageF* depth_map = nullptr;  //!< the camera's (blurred) depth; required unless test is Binary with none
};

//! Silhouette edges of the non-foliage meshes of ps.scene seen from ps.camera — edges between a
//! triangle facing the camera and one facing away, vertices welded by exact position (UV seams
//! split vertices) — chained into polylines in a deterministic order (instance, primitive,
//! triangle). Open boundary edges are not contours. Contour strokes carry no normals (no n·v fade:
//! a silhouette's n·v is 0 by definition).
//! Uses ps.contours when set (built once per job), else builds the cache for this call. The facing
//! and silhouette tests run on ex's threads (the same strokes for any traversal and thread count).
std::vector<Stroke> contour_strokes(const PassScene& ps, const Exec& ex = {});

//! What contour extraction needs that does not depend on the view, per non-foliage primitive:
//! world positions, vertices welded by exact position, and the welded edges (sorted pairs) with
//! the triangles using them. Built once per render job (raster::PassScene::contours).
struct ContourCache {
    struct Edge {
        std::uint32_t a, b;                  //!< welded vertex pair, a < b
        std::uint32_t uses_begin, uses_end;  //!< range of `uses`
    };
    struct Mesh {
        const scene::Primitive* prim = nullptr;
        std::vector<glm::vec3> world;
        std::vector<std::uint32_t> weld;
        std::vector<Edge> edges;           //!< sorted by (a, b)
        std::vector<std::uint32_t> uses;   //!< 3 x triangle + edge slot, increasing per edge
    };
    std::vector<Mesh> meshes;  //!< instances, then primitives, in scene order
};
ContourCache build_contour_cache(const scene::Scene& sc);
//! contour_strokes from a cache of ps.scene (the same strokes as building it anew).
std::vector<Stroke> contour_strokes(const PassScene& ps, const ContourCache& cache, const Exec& ex = {});

//! Draws `strokes` in order into `out` (1 channel at the pass size, background 0): per stroke, every
//! covered pixel once, a = alpha·f_v·fades, dst = a + dst·(1 - a) (an ink-coverage map, "over").
//! Non-finite points split a stroke (dropped segments counted in *dropped). Throws aq::Error for
//! invalid parameters or counts beyond the documented limits.
void render_strokes(ImageF& out, const PassScene& ps, const std::vector<Stroke>& strokes, const StrokeParams& p,
                    const Exec& ex = {}, std::size_t* dropped = nullptr);
//! The strokes of several lists, in list order (the scene's, then the contours: no copy per frame).
void render_strokes(ImageF& out, const PassScene& ps, std::span<const std::vector<Stroke>* const> lists,
                    const StrokeParams& p, const Exec& ex = {}, std::size_t* dropped = nullptr);

}  // namespace aq::raster
