// reference/stage_inputs.h — inputs for the GPU-equivalent checks and the GL benchmarks: any stage
// input target resolved by running its registered producer (C++) on a G-buffer (the synthetic one
// of tests/synthetic_gbuffer.h, or a rendered one), so that every stage sees realistic upstream
// data (half-resolution intermediates included).
#pragma once

#include <string>
#include <vector>

#include "core/targets.h"
#include "stylize/stage.h"

namespace aq::ref {

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
