// reference/stage_inputs.cpp — producer-driven input resolution for the GPU-equivalent checks.
#include "reference/stage_inputs.h"

namespace aq::ref {

std::vector<ImageF> run_cpp_stage(const stylize::StageVariant& v, const Targets& t, const stylize::ParamValues& p,
                                  const stylize::Globals& globals, const Exec& ex) {
    stylize::StageIO io;
    io.globals = &globals;
    for (auto& port : v.inputs) io.in.push_back(t.has(port.default_target) ? &t.get(port.default_target) : nullptr);
    std::vector<ImageF> outs(v.outputs.size());
    for (auto& o : outs) io.out.push_back(&o);
    v.run(io, p, ex);
    return outs;
}

bool resolve_target(Targets& t, const std::string& name, const stylize::Globals& globals) {
    if (t.has(name)) return true;
    const auto& reg = stylize::builtin_registry();
    const stylize::StageVariant* producer = nullptr;
    for (auto& stage : reg.stages()) {
        for (auto* v : reg.variants(stage)) {
            for (auto& o : v->outputs)
                if (o.default_target == name && !producer) producer = v;
        }
    }
    if (!producer) return false;
    for (auto& in : producer->inputs) {
        if (in.default_target == name) continue;  // a stage never reads its own output
        if (!resolve_target(t, in.default_target, globals) && !in.optional) return false;
    }
    auto params = stylize::Registry::resolve_params(*producer, {}, "resolve_target");
    auto outs = run_cpp_stage(*producer, t, params, globals);
    for (std::size_t k = 0; k < outs.size(); ++k)
        if (!t.has(producer->outputs[k].default_target)) t.set(producer->outputs[k].default_target, std::move(outs[k]));
    return true;
}

}  // namespace aq::ref
