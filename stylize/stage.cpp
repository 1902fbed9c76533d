// stylize/stage.cpp — registry storage, lookup and parameter validation.
#include "stylize/stage.h"

#include <map>
#include <mutex>

#include <cmath>
#include <sstream>

#include "stylize/stages/toolkit.h"

namespace aq::stylize {

void check_io(const std::string& key, const std::vector<Port>& inputs, const std::vector<Port>& outputs,
              const StageIO& io) {
    if (io.in.size() != inputs.size() || io.out.size() != outputs.size())
        throw Error(key + ": called with " + std::to_string(io.in.size()) + " inputs and " + std::to_string(io.out.size()) +
                    " outputs, expected " + std::to_string(inputs.size()) + " and " + std::to_string(outputs.size()));
    for (std::size_t k = 0; k < inputs.size(); ++k) {
        const ImageF* img = io.in[k];
        if (!img || img->empty()) {
            if (inputs[k].optional) continue;
            throw Error(key + ": required input '" + inputs[k].name + "' is missing or empty");
        }
        if (img->channels() != inputs[k].channels)
            throw Error(key + ": input '" + inputs[k].name + "' has " + std::to_string(img->channels()) + " channels, expected " +
                        std::to_string(inputs[k].channels));
    }
    for (std::size_t k = 0; k < inputs.size(); ++k) {  // the size relations, once every input is there
        const Port& p = inputs[k];
        if (p.size == SizeRule::Any || !io.in[k] || io.in[k]->empty()) continue;
        const ImageF* like = io.in[std::size_t(port_index(inputs, p.like))];
        if (!like || like->empty()) continue;  // an absent optional input relates to nothing
        if (p.size == SizeRule::Same) toolkit::check_same_size(*io.in[k], *like, key, p.name, p.like);
        else toolkit::check_full_or_half(*io.in[k], *like, key, p.name, p.like);
    }
    for (std::size_t k = 0; k < outputs.size(); ++k)
        if (!io.out[k]) throw Error(key + ": output '" + outputs[k].name + "' has no destination");
}

void Registry::add(StageVariant v) {
    if (has(v.stage, v.variant)) throw Error("stage variant '" + v.key() + "' registered twice");
    if (!v.run) throw Error("stage variant '" + v.key() + "' has no run function");
    for (std::size_t k = 0; k < v.params.size(); ++k)
        if (find_param(v.params, v.params[k].name) != &v.params[k])
            throw Error("stage variant '" + v.key() + "' declares parameter '" + v.params[k].name + "' twice");
    if (!v.in_place_input.empty() || !v.in_place_output.empty()) {
        const Port* in = find_port(v.inputs, v.in_place_input);
        const Port* out = find_port(v.outputs, v.in_place_output);
        if (!in || !out || in->channels != out->channels)
            throw Error("stage variant '" + v.key() + "': in place from input '" + v.in_place_input + "' to output '" +
                        v.in_place_output + "' needs both ports, with the same channel count");
    }
    for (const Port& p : v.inputs)
        if ((p.size == SizeRule::Any) != p.like.empty() || (!p.like.empty() && (p.like == p.name || !find_port(v.inputs, p.like))))
            throw Error("stage variant '" + v.key() + "': input '" + p.name +
                        "' relates its size to '" + p.like + "', which is not another input (or has no rule)");
    // Framework entry check, shared by every stage (check_io), on both ways in: run and the
    // bound step a compiled pipeline keeps.
    v.run = [inner = std::move(v.run), key = v.key(), inputs = v.inputs, outputs = v.outputs](
                StageIO& io, const ParamValues& params, const Exec& ex) {
        check_io(key, inputs, outputs, io);
        inner(io, params, ex);
    };
    if (v.bind)
        v.bind = [inner = std::move(v.bind), key = v.key(), inputs = v.inputs, outputs = v.outputs](const ParamValues& params) {
            return StepFn([step = inner(params), key, inputs, outputs](StageIO& io, const Exec& ex) {
                check_io(key, inputs, outputs, io);
                step(io, ex);
            });
        };
    variants_.push_back(std::move(v));
}

const ParamDesc* find_param(const std::vector<ParamDesc>& params, const std::string& name) {
    for (const ParamDesc& p : params)
        if (p.name == name) return &p;
    return nullptr;
}

StepFn StageVariant::bound(const ParamValues& params) const {
    if (bind) return bind(params);
    return [run = run, params](StageIO& io, const Exec& ex) { run(io, params, ex); };
}

const char* param_kind_name(ParamKind k) {
    switch (k) {
        case ParamKind::Int: return "int";
        case ParamKind::Bool: return "bool";
        default: return "float";
    }
}

const Port* find_port(const std::vector<Port>& ports, const std::string& name) {
    for (const Port& p : ports)
        if (p.name == name) return &p;
    return nullptr;
}

int port_index(const std::vector<Port>& ports, const std::string& name) {
    const Port* p = find_port(ports, name);
    return p ? int(p - ports.data()) : -1;
}

void Registry::add_fusion(Fusion f) {
    const StageVariant* pv = nullptr;
    const StageVariant* cv = nullptr;
    for (const StageVariant& v : variants_) {
        if (v.key() == f.producer) pv = &v;
        if (v.key() == f.consumer) cv = &v;
    }
    if (!pv || !cv) throw Error("fusion " + f.producer + " -> " + f.consumer + ": unknown stage variant");
    if (!f.run) throw Error("fusion " + f.producer + " -> " + f.consumer + ": no run function");
    if (fusion(f.producer, f.consumer)) throw Error("fusion " + f.producer + " -> " + f.consumer + " registered twice");
    for (const auto& [out, in] : f.links) {
        const Port* o = find_port(pv->outputs, out);
        const Port* i = find_port(cv->inputs, in);
        if (!o || !i || o->channels != i->channels)
            throw Error("fusion " + f.producer + " -> " + f.consumer + ": link " + out + " -> " + in + " does not match the ports");
    }
    for (const Port& o : pv->outputs) {
        bool linked = false;
        for (const auto& l : f.links) linked = linked || l.first == o.name;
        if (!linked) throw Error("fusion " + f.producer + " -> " + f.consumer + ": output '" + o.name + "' has no link");
    }
    fusions_.push_back(std::move(f));
}

const Fusion* Registry::fusion(const std::string& producer, const std::string& consumer) const {
    for (const Fusion& f : fusions_)
        if (f.producer == producer && f.consumer == consumer) return &f;
    return nullptr;
}

bool Registry::has(const std::string& stage, const std::string& variant) const {
    for (auto& v : variants_)
        if (v.stage == stage && v.variant == variant) return true;
    return false;
}

const StageVariant& Registry::get(const std::string& stage, const std::string& variant) const {
    for (auto& v : variants_)
        if (v.stage == stage && v.variant == variant) return v;
    std::string have;
    for (auto* v : variants(stage)) have += (have.empty() ? "" : ", ") + v->variant;
    if (have.empty()) {
        std::string all;
        for (auto& s : stages()) all += (all.empty() ? "" : ", ") + s;
        throw Error("unknown stage '" + stage + "' (stages: " + all + ")");
    }
    throw Error("unknown variant '" + variant + "' of stage '" + stage + "' (variants: " + have + ")");
}

const StageVariant& Registry::default_variant(const std::string& stage) const {
    auto vs = variants(stage);
    if (vs.empty()) return get(stage, "");  // throws with the list of stages
    return *vs.front();
}

std::vector<std::string> Registry::stages() const {
    std::vector<std::string> out;
    for (auto& v : variants_) {
        bool seen = false;
        for (auto& s : out) seen |= (s == v.stage);
        if (!seen) out.push_back(v.stage);
    }
    return out;
}

std::vector<const StageVariant*> Registry::variants(const std::string& stage) const {
    std::vector<const StageVariant*> out;
    for (auto& v : variants_)
        if (v.stage == stage) out.push_back(&v);
    return out;
}

std::vector<const StageVariant*> Registry::all() const {
    std::vector<const StageVariant*> out;
    for (auto& v : variants_) out.push_back(&v);
    return out;
}

double Registry::param_value(const StageVariant& v, const std::string& name, const std::string& text,
                             const std::string& where) {
    const ParamDesc* d = find_param(v.params, name);
    if (d)
        for (std::size_t k = 0; k < d->names.size(); ++k)
            if (d->names[k] == text) return double(k);
    if (text == "true") return 1;
    if (text == "false") return 0;
    char* end = nullptr;
    const double x = std::strtod(text.c_str(), &end);
    if (!text.empty() && end == text.c_str() + text.size()) return x;
    std::string names;
    if (d)
        for (const std::string& n : d->names) names += (names.empty() ? "" : ", ") + n;
    throw Error(where + ": '" + text + "' is not a number" + (names.empty() ? "" : " or one of " + names));
}

ParamValues Registry::resolve_params(const StageVariant& v, const std::map<std::string, double>& overrides,
                                     const std::string& where) {
    ParamValues out;
    for (auto& d : v.params) out[d.name] = d.def;
    for (auto& [name, value] : overrides) {
        const ParamDesc* d = find_param(v.params, name);
        if (!d) {
            std::string have;
            for (auto& p : v.params) have += (have.empty() ? "" : ", ") + p.name;
            throw Error(where + ": unknown parameter '" + name + "' of " + v.key() + " (parameters: " +
                        (have.empty() ? "none" : have) + ")");
        }
        std::ostringstream range;
        range << "[" << d->lo << ", " << d->hi << "]";
        if (!std::isfinite(value) || value < d->lo || value > d->hi) {
            std::ostringstream msg;
            msg << where << ": " << v.key() << "." << name << " = " << value << " is outside " << range.str();
            throw Error(msg.str());
        }
        if (d->kind == ParamKind::Int && value != std::floor(value))
            throw Error(where + ": " + v.key() + "." + name + " must be an integer");
        if (d->kind == ParamKind::Bool && value != 0.0 && value != 1.0)
            throw Error(where + ": " + v.key() + "." + name + " must be true/false (1/0)");
        out[name] = value;
    }
    return out;
}

const Registry& builtin_registry() {
    static const Registry r = [] {
        Registry reg;
        register_builtin_stages(reg);
        return reg;
    }();
    return r;
}

namespace {
std::mutex& runtime_mutex() {
    static std::mutex m;
    return m;
}
//! By stage name; every registry ever made stays alive (compiled steps point into them). The map
//! is never destroyed either, so the registries stay reachable until the process ends (no leak
//! for LeakSanitizer: tests/stylize/writing_a_stage_test.cpp registers one under the sanitizers).
std::map<std::string, const Registry*>& runtime_stages() {
    static auto* m = new std::map<std::string, const Registry*>;
    return *m;
}
}  // namespace

void register_runtime_stage(StageVariant v) {
    if (!builtin_registry().variants(v.stage).empty() || !builtin_pass_registry().variants(v.stage).empty())
        throw Error("stage '" + v.stage + "' is a built-in stage: give the prototype another name");
    if (v.stage.empty() || v.variant.empty() || !v.run) throw Error("a registered stage needs a name, a variant name and a function");
    auto* r = new Registry;  // never freed: compiled pipelines keep pointers to its variant
    const std::string name = v.stage;
    r->add(std::move(v));
    std::lock_guard<std::mutex> lock(runtime_mutex());
    static auto* replaced = new std::vector<const Registry*>;  // still reachable, as above
    if (const auto it = runtime_stages().find(name); it != runtime_stages().end()) replaced->push_back(it->second);
    runtime_stages()[name] = r;
}

const Registry* runtime_registry(const std::string& stage) {
    std::lock_guard<std::mutex> lock(runtime_mutex());
    const auto it = runtime_stages().find(stage);
    return it == runtime_stages().end() ? nullptr : it->second;
}

const Registry& builtin_pass_registry() {
    static const Registry r = [] {
        Registry reg;
        register_builtin_passes(reg);
        return reg;
    }();
    return r;
}

}  // namespace aq::stylize
