// reference/synthetic.h — inputs for the GPU-equivalent checks and the GL benchmarks: a synthetic
// but rich G-buffer, and the resolution of any stage input target by running its registered
// producer (C++) so that every stage sees realistic upstream data (half-resolution intermediates
// included).
#pragma once

#include <cstdint>
#include <string>

#include "core/targets.h"
#include "stylize/stage.h"

namespace aq::ref {

//! Every G-buffer target of spec §1 at w x h: `color` (smooth gradients, hard object edges,
//! coverage in alpha, background alpha 0), the four `ctrl.*` targets (painted patches, soft and
//! hard, values over the whole signed range [-1, 1]), `depth.linear` (slanted planes, steps, +inf
//! background), `normal` (view space, spheres and planes), `object_id`, `diffuse`, `specular`.
//! Deterministic in (w, h, seed).
Targets synthetic_gbuffer(int w, int h, std::uint32_t seed = 1);

//! A smooth-plus-edges pattern in [0, 1] with `channels` channels, for inputs nothing produces.
ImageF synthetic_pattern(int w, int h, int channels, std::uint32_t seed);

//! Makes sure `name` exists in t: if absent, finds the registered variant whose output port
//! defaults to `name` (the stage's first-registered variant preferred), resolves its inputs the
//! same way, and runs it (C++, reference traversal, default parameters). Returns false when no
//! variant produces it. `globals` is passed to the producers.
bool resolve_target(Targets& t, const std::string& name, const stylize::Globals& globals);

//! Runs the C++ stage variant on targets (inputs by default target names, absent optional inputs
//! as nullptr) and returns its outputs in port order.
std::vector<ImageF> run_cpp_stage(const stylize::StageVariant& v, const Targets& t, const stylize::ParamValues& p,
                                  const stylize::Globals& globals, const Exec& ex = Exec::reference());

}  // namespace aq::ref
