// reference/pass_twin.h — the LD06 raster-pass twin: raster::render_triangle_pass's depth tests,
// values and blend modes as a GLSL vertex + fragment shader pair (reference/shaders/pass.{vert,frag}
// .glsl) drawn by the OpenGL rasterizer with GL's own depth test and blending (docs/reference.md
// "LD06 raster passes").
#pragma once

#include "core/image.h"
#include "raster/pass.h"

namespace aq::ref {

//! The same single-channel map as raster::render_triangle_pass(ps, p), drawn with OpenGL. The view
//! set-up (raster::pass_view) is shared; everything per vertex and per fragment is GLSL. Throws
//! aq::Error (no GL context, invalid pass).
ImageF render_triangle_pass_gl(const raster::PassScene& ps, const raster::TrianglePass& p);

}  // namespace aq::ref
