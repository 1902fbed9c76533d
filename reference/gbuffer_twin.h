// reference/gbuffer_twin.h — the G-buffer twin: raster/'s vertex stage (transform, hand tremor,
// bleeding displacement) and watercolor material as a GLSL vertex + fragment shader pair
// (reference/shaders/gbuffer.{vert,frag}.glsl), drawn with the same geometry into float MRTs by
// the OpenGL rasterizer (docs/reference.md "G-buffer").
#pragma once

#include "core/targets.h"
#include "raster/raster.h"
#include "scenes/scene.h"

namespace aq::ref {

//! Renders the same ten targets as raster::render_gbuffer (color, ctrl.*, depth.linear, normal,
//! object_id, diffuse, specular; same background values) with OpenGL. settings.ssaa must be 1
//! (the twin checks the rasterizer and material, not the resolve). Throws aq::Error.
Targets render_gbuffer_gl(const scene::Scene& scene, const scene::Camera& camera,
                          const raster::RenderSettings& settings);

}  // namespace aq::ref
