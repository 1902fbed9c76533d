// raster/vertex.h — vertex stage: projection, WC17 hand tremor (eq. 1-2, MNPR form), WC17 §3.2
// bleeding displacement, per-vertex fixed-point snapping and clip outcodes.
//
// Everything here is a pure per-vertex function; vertex_stage() only schedules it (serially for
// the reference traversal, in parallel over vertex ranges for the fast one). Each output element
// depends on its input vertex only, so the results do not depend on the schedule.
#pragma once

#include <cstdint>
#include <memory>
#include <type_traits>
#include <vector>

#include <glm/glm.hpp>

#include "raster/raster.h"

namespace aq::raster {

//! Fixed-point subpixel precision: 8 bits (1/256 px).
inline constexpr int kSubpixelBits = 8;
inline constexpr int kSubpixelOne = 1 << kSubpixelBits;
//! Guard band: snapped coordinates stay within +-kGuardBandPx pixels, so fixed-point values are
//! within +-2^29, edge deltas within 2^30 (int32) and edge-function products within 2^61 (int64).
inline constexpr double kGuardBandPx = double(1 << 21);

// Clip outcode bits.
enum : std::uint32_t {
    kOutNear = 1, kOutFar = 2, kOutLeft = 4, kOutRight = 8, kOutBottom = 16, kOutTop = 32,
    kOutNonFinite = 64,
};

//! Projection matrix (OpenGL clip conventions, z in [-w, w]) for the camera at image aspect
//! `aspect` (used when the camera has none). Written out explicitly (docs/raster.md).
glm::mat4 projection_matrix(const scene::Camera& cam, float image_aspect);

//! MNPR/WC17 hand tremor offset in output pixels for one vertex (docs/raster.md "Vertex stage"):
//!   phase = (T * speed) * 100; w = min(sat(1.2 * dot(N, V)), 1 - front)
//!   off   = sin(phase + (p_obj.xy * frequency) * 10) * tremor_px * w
glm::vec2 tremor_offset_px(const TremorParams& p, float time_s, glm::vec3 p_obj, glm::vec3 n_view,
                           glm::vec3 v_view);

//! WC17 §3.2 bleeding displacement (MNPR): p + n * sat(ctrl_bleed - 0.7) * 0.5.
glm::vec3 bleed_displace(glm::vec3 p_obj, glm::vec3 n_obj, float ctrl_bleed);

//! Viewport mapping shared by the per-vertex snap and the clipper.
struct Viewport {
    int width = 0, height = 0;  //!< raster grid (supersampled size)
    double gb_x = 1, gb_y = 1;  //!< guard band in NDC units (|x/w| <= gb_x)
};

//! One snapped vertex: fixed-point screen position (y down, pixel centres at +0.5),
//! 1/w and linear eye depth.
struct SnapVertex {
    std::int32_t x, y;
    //! outcode; x, y, inv_w are only meaningful when 0. Third, so that the batch setup reads x, y
    //! and code in one 16-byte load.
    std::uint32_t code;
    float inv_w, depth;
};

//! Per-render array without value-initialisation (every element is written by the vertex stage
//! before it is read): saves a zero-fill pass over tens of MB per frame.
template <class T>
class UninitArray {
    static_assert(std::is_trivially_default_constructible_v<T>);
public:
    //! Keeps the buffer when it is large enough (frame scratch reused between frames).
    void resize(std::size_t n) {
        if (n > cap_) {
            p_.reset(new T[n]);
            cap_ = n;
        }
        n_ = n;
    }
    void clear() { n_ = 0; }
    T& operator[](std::size_t i) { return p_[i]; }
    const T& operator[](std::size_t i) const { return p_[i]; }
    std::size_t size() const { return n_; }
    bool empty() const { return n_ == 0; }
private:
    std::unique_ptr<T[]> p_;
    std::size_t n_ = 0;
    std::size_t cap_ = 0;
};

//! Outcode of a clip-space position against near/far and the guard band; kOutNonFinite if any
//! component is NaN/Inf.
std::uint32_t outcode(const glm::vec4& clip, const Viewport& vp);

//! Snaps a clip-space position that is inside near/far and the guard band (outcode 0).
//! depth: the linear eye depth attribute of this vertex (interpolated perspective-correctly).
SnapVertex snap_vertex(const glm::vec4& clip, float depth, const Viewport& vp);

//! The transformed vertices of one draw (instance x primitive).
struct DrawVertices {
    const scene::Primitive* prim = nullptr;
    const scene::Material* mat = nullptr;
    std::uint32_t object_id = 0;
    UninitArray<glm::vec4> clip;         //!< after tremor
    //! View-space position (after bleeding displacement) and unit normal, interleaved: the
    //! shading pass gathers both for the three vertices of each pixel's triangle.
    struct Shading {
        glm::vec3 pos, normal;
    };
    UninitArray<Shading> view;
    UninitArray<glm::vec4> view_tangent; //!< xyz view space, w handedness; empty if none
    UninitArray<SnapVertex> snap;        //!< outcode + snapped position (one cache access in setup)
    //! The draw's base_color_working where it cannot vary over the draw (FragmentInput::base).
    bool const_base = false;
    glm::vec3 base{0};
};

struct FrameParams {
    glm::mat4 proj{1.0f};
    bool perspective = true;
    Viewport vp;
    int out_width = 1, out_height = 1;  //!< final (resolved) size; the tremor is in these pixels
    float time_s = 0;
    const RenderSettings* settings = nullptr;
};

//! Transforms one draw's vertices [begin, end) into dv (already sized): eight at a time (AVX2),
//! each with transform_vertex's operations (schedule only; a NaN's payload may differ).
void transform_vertices(const FrameParams& fp, const glm::mat4& model_view, const glm::mat3& normal_mat,
                        DrawVertices& dv, std::size_t begin, std::size_t end);

//! Vertex i of the draw, alone: the vertex stage's maths (the plain reference of transform_vertices).
void transform_vertex(const FrameParams& fp, const glm::mat4& mv, const glm::mat3& nm, DrawVertices& dv,
                      std::size_t i);

}  // namespace aq::raster
