// reference/pass_twin.h — the LD06 raster-pass twin: raster::render_triangle_pass's depth tests,
// values and blend modes as a GLSL vertex + fragment shader pair (reference/shaders/pass.{vert,frag}
// .glsl) drawn by the OpenGL rasterizer with GL's own depth test and blending (docs/reference.md
// "LD06 raster passes").
#pragma once

#include "core/image.h"
#include "raster/particles.h"
#include "raster/pass.h"
#include "raster/strokes.h"

#include <array>

namespace aq::ref {

//! The same single-channel map as raster::render_triangle_pass(ps, p), drawn with OpenGL. The view
//! set-up (raster::pass_view) is shared; everything per vertex and per fragment is GLSL. Throws
//! aq::Error (no GL context, invalid pass).
ImageF render_triangle_pass_gl(const raster::PassScene& ps, const raster::TrianglePass& p);

//! The dark, medium and bright maps of raster::render_particles, drawn as GL points (size from
//! eq. 10 in the vertex shader) with additive blending. Placement (eq. 8-9, 11) is the shared
//! preprocessing step, as in the paper. Throws aq::Error.
std::array<ImageF, 3> render_particles_gl(const raster::PassScene& ps, const std::vector<raster::Particle>& particles,
                                          const raster::ParticleParams& p);

//! raster::render_strokes drawn with OpenGL: per stroke, one quad per segment whose fragment
//! shader decides coverage (distance to the projected segment), picks the nearest segment with the
//! depth test and computes the alpha (eq. 2 visibility, the §4.4 fades); then the stroke's map is
//! composited "over" the result with GL blending, stroke after stroke. Host side: the view set-up
//! (raster::pass_view, shared) and the segments' view-space ends clipped at the near plane. Throws
//! aq::Error.
ImageF render_strokes_gl(const raster::PassScene& ps, const std::vector<raster::Stroke>& strokes,
                         const raster::StrokeParams& p);

}  // namespace aq::ref
