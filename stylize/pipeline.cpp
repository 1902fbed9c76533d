// stylize/pipeline.cpp — JSON pipeline files, command-line overrides, validation and the runner.
#include "stylize/pipeline.h"

#include "core/input.h"
#include "core/json_file.h"

#include <algorithm>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "stylize/kernels.h"
#include "stylize/schedule/bands.h"
#include "stylize/schedule/plan.h"
#include "raster/pass.h"  // the scene's size when a pipeline starts with raster passes

#ifndef AQ_PRESET_DIR
#define AQ_PRESET_DIR "stylize/presets"
#endif

namespace aq::stylize {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string idx(const std::string& key, std::size_t i) { return key + "[" + std::to_string(i) + "]"; }

// The project's one JSON reader (core/json_file.h JsonReader), with the pipeline file as `where`.
[[noreturn]] void fail(const std::string& src, const std::string& key, const std::string& msg) {
    JsonReader{src}.bad(key, msg);
}

void check_keys(const json& j, std::initializer_list<const char*> allowed, const std::string& src, const std::string& key) {
    JsonReader{src}.check_keys(j, key, allowed);
}

std::string get_string(const json& j, const std::string& src, const std::string& key) {
    return JsonReader{src}.string(j, key);
}

double get_number(const json& j, const std::string& src, const std::string& key) {
    return JsonReader{src}.number_or_flag(j, key);
}

std::string port_list(const std::vector<Port>& ports) {
    std::string s;
    for (auto& p : ports) s += (s.empty() ? "" : ", ") + p.name;
    return s.empty() ? "none" : s;
}

const Registry& registry_of(const PipelineStep& s) {
    if (s.pass) return builtin_pass_registry();
    if (builtin_registry().variants(s.stage).empty())
        if (const Registry* r = runtime_registry(s.stage)) return *r;  // a stage registered at run time (Python)
    return builtin_registry();
}

//! Checks one step against the registry; `key` is "steps[i]". `named`: parameters the file gives
//! by a name of their value ("border": "mirror"), set into s.params once the variant is known.
void check_step(PipelineStep& s, const std::map<std::string, std::string>& named, const std::string& src,
                const std::string& key) {
    const Registry& reg = registry_of(s);
    const StageVariant* v = nullptr;
    try {
        v = s.variant.empty() ? &reg.default_variant(s.stage) : &reg.get(s.stage, s.variant);
    } catch (const Error& e) {
        fail(src, key + (s.variant.empty() || reg.variants(s.stage).empty() ? (s.pass ? ".pass" : ".stage") : ".variant"), e.what());
    }
    for (const auto& [name, text] : named)
        s.params[name] = Registry::param_value(*v, name, text, src + ": " + key + ".params." + name);
    for (auto& [name, value] : s.params) {
        Registry::resolve_params(*v, {{name, value}}, src + ": " + key + ".params." + name);
    }
    for (auto& [port, target] : s.in) {
        if (!find_port(v->inputs, port))
            fail(src, key + ".in." + port, "unknown input port of " + v->key() + " (ports: " + port_list(v->inputs) + ")");
        if (target.empty()) fail(src, key + ".in." + port, "empty target name");
    }
    for (auto& [port, target] : s.out) {
        if (!find_port(v->outputs, port))
            fail(src, key + ".out." + port, "unknown output port of " + v->key() + " (ports: " + port_list(v->outputs) + ")");
        if (target.empty()) fail(src, key + ".out." + port, "empty target name");
    }
}

std::string shared_assets_guess() {
    if (const char* s = std::getenv("AQ_SHARED")) return std::string(s) + "/assets";
    // <repo>/stylize/presets -> <repo>/../shared/assets
    return (fs::path(AQ_PRESET_DIR) / ".." / ".." / ".." / "shared" / "assets").lexically_normal().string();
}

std::string resolve_paper_path(const std::string& file, const std::string& base_dir) {
    fs::path p(file);
    if (p.is_absolute()) return file;
    if (!base_dir.empty() && fs::exists(fs::path(base_dir) / p)) return (fs::path(base_dir) / p).string();
    const fs::path s = fs::path(shared_assets_guess()) / p;
    if (fs::exists(s)) return s.string();
    return file;  // prepare_paper reports the unreadable path
}

}  // namespace

std::string preset_dir() {
    if (const char* d = std::getenv("AQ_PRESET_DIR"); d && *d) return d;
    return AQ_PRESET_DIR;
}

std::vector<std::string> preset_names() {
    std::vector<std::string> out;
    std::error_code ec;
    for (auto& e : fs::directory_iterator(preset_dir(), ec))
        if (e.path().extension() == ".json") out.push_back(e.path().stem().string());
    std::sort(out.begin(), out.end());
    return out;
}

Pipeline parse_pipeline(const std::string& text, const std::string& src, const std::string& base_dir) {
    const json j = parse_json(text, src);
    if (!j.is_object()) fail(src, "", "expected a JSON object at the top level");
    check_keys(j, {"name", "doc", "substrate_color", "paper", "steps", "output", "default_control", "foliage", "$schema",
                   "comment"},
               src, "");
    Pipeline p;
    p.source = src;
    p.name = j.contains("name") ? get_string(j["name"], src, "name") : fs::path(src).stem().string();
    if (j.contains("doc")) p.doc = get_string(j["doc"], src, "doc");
    if (j.contains("output")) p.output = get_string(j["output"], src, "output");
    if (j.contains("default_control")) {
        if (!j["default_control"].is_array()) fail(src, "default_control", "expected an array of control rules");
        p.default_control = j["default_control"].dump();
    }
    if (j.contains("substrate_color")) {
        const json& c = j["substrate_color"];
        if (!c.is_array() || c.size() != 3) fail(src, "substrate_color", "expected [r, g, b]");
        for (int k = 0; k < 3; ++k) {
            const double v = get_number(c[std::size_t(k)], src, idx("substrate_color", std::size_t(k)));
            if (!(v >= 0.0 && v <= 1.0)) fail(src, idx("substrate_color", std::size_t(k)), "must be in [0, 1]");
            p.substrate_color[k] = float(v);
        }
    }
    if (j.contains("paper") && !j["paper"].is_null()) {
        const json& pj = j["paper"];
        if (!pj.is_object()) fail(src, "paper", "expected an object {file, layout, scale, roughness}");
        check_keys(pj, {"file", "layout", "scale", "roughness"}, src, "paper");
        if (!pj.contains("file")) fail(src, "paper.file", "missing");
        p.paper.file = resolve_paper_path(get_string(pj["file"], src, "paper.file"), base_dir);
        if (pj.contains("layout")) {
            p.paper.layout = get_string(pj["layout"], src, "paper.layout");
            if (p.paper.layout != "mnpr" && p.paper.layout != "height")
                fail(src, "paper.layout", "expected \"mnpr\" or \"height\"");
        }
        if (pj.contains("scale")) {
            const double v = get_number(pj["scale"], src, "paper.scale");
            if (!(v >= 0.1 && v <= 10)) fail(src, "paper.scale", "must be in [0.1, 10]");
            p.paper.scale = float(v);
        }
        if (pj.contains("roughness")) {
            const double v = get_number(pj["roughness"], src, "paper.roughness");
            if (!(v >= 0 && v <= 5)) fail(src, "paper.roughness", "must be in [0, 5]");
            p.paper.roughness = float(v);
        }
        p.has_paper = true;
    }
    if (j.contains("foliage")) {
        const json& fj = j["foliage"];
        if (!fj.is_object()) fail(src, "foliage", "expected an object {abstract, T, radius, relative, cells_per_radius, fit, technique}");
        check_keys(fj, {"abstract", "T", "radius", "relative", "cells_per_radius", "fit", "fit_threshold", "technique", "comment"}, src,
                   "foliage");
        raster::FoliageParams& f = p.foliage;
        auto number = [&](const char* k, double lo, double hi) {
            const double v = get_number(fj[k], src, std::string("foliage.") + k);
            if (!(v >= lo && v <= hi)) {
                std::ostringstream m;
                m << "must be in [" << lo << ", " << hi << "]";
                fail(src, std::string("foliage.") + k, m.str());
            }
            return v;
        };
        if (fj.contains("abstract")) f.abstract = number("abstract", 0, 1) != 0;
        if (fj.contains("T")) f.threshold = float(number("T", 1e-6, 1e6));
        if (fj.contains("radius")) f.radius = float(number("radius", 1e-6, 1e6));
        if (fj.contains("relative")) f.relative = number("relative", 0, 1) != 0;
        // "fit_threshold" (before 2026-12-05: halve T until a surface exists) now means the fit.
        for (const char* k : {"fit", "fit_threshold"})
            if (fj.contains(k)) f.fit = number(k, 0, 1) != 0;
        if (fj.contains("technique")) {
            if (!fj["technique"].is_string()) fail(src, "foliage.technique", "expected \"auto\", \"surface\" or \"texture\"");
            try {
                f.technique = raster::parse_technique(fj["technique"].get<std::string>());
            } catch (const Error& e) {
                fail(src, "foliage.technique", e.what());
            }
        }
        if (fj.contains("cells_per_radius")) {
            const double c = number("cells_per_radius", 1, 16);
            if (c != std::floor(c)) fail(src, "foliage.cells_per_radius", "must be an integer");
            f.cells_per_radius = int(c);
        }
        p.has_foliage = true;
    }
    if (!j.contains("steps")) fail(src, "steps", "missing");
    const json& steps = j["steps"];
    if (!steps.is_array()) fail(src, "steps", "expected an array of steps");
    for (std::size_t i = 0; i < steps.size(); ++i) {
        const std::string key = idx("steps", i);
        const json& sj = steps[i];
        if (!sj.is_object()) fail(src, key, "expected an object");
        check_keys(sj, {"stage", "pass", "variant", "params", "in", "out", "id", "doc"}, src, key);
        PipelineStep s;
        if (sj.contains("stage") == sj.contains("pass"))
            fail(src, key, "a step names either a \"stage\" (image stage) or a \"pass\" (raster pass)");
        s.pass = sj.contains("pass");
        const char* kind = s.pass ? "pass" : "stage";
        s.stage = get_string(sj[kind], src, key + "." + kind);
        if (sj.contains("variant")) s.variant = get_string(sj["variant"], src, key + ".variant");
        s.id = sj.contains("id") ? get_string(sj["id"], src, key + ".id") : s.stage;
        std::map<std::string, std::string> named;
        if (sj.contains("params")) {
            if (!sj["params"].is_object()) fail(src, key + ".params", "expected an object");
            for (auto it = sj["params"].begin(); it != sj["params"].end(); ++it)
                if (it.value().is_string()) named[it.key()] = it.value().get<std::string>();
                else s.params[it.key()] = get_number(it.value(), src, key + ".params." + it.key());
        }
        for (const char* dir : {"in", "out"}) {
            if (!sj.contains(dir)) continue;
            if (!sj[dir].is_object()) fail(src, key + "." + dir, "expected an object {port: target}");
            for (auto it = sj[dir].begin(); it != sj[dir].end(); ++it)
                (dir[0] == 'i' ? s.in : s.out)[it.key()] =
                    get_string(it.value(), src, key + "." + dir + "." + it.key());
        }
        check_step(s, named, src, key);
        p.steps.push_back(std::move(s));
    }
    if (p.steps.empty()) fail(src, "steps", "a pipeline needs at least one step");
    return p;
}

Pipeline load_pipeline(const std::string& name_or_path) {
    fs::path path(name_or_path);
    const bool is_path = path.has_extension() || name_or_path.find('/') != std::string::npos;
    if (!is_path) {
        path = fs::path(preset_dir()) / (name_or_path + ".json");
        if (!fs::exists(path)) {
            std::string have;
            for (auto& n : preset_names()) have += (have.empty() ? "" : ", ") + n;
            throw Error("unknown style '" + name_or_path + "' (presets in " + preset_dir() + ": " +
                        (have.empty() ? "none" : have) + ")");
        }
    }
    const std::string text = read_input_text(path.string(), kMaxJsonFileBytes, "style file");
    return parse_pipeline(text, path.string(), path.parent_path().string());
}

namespace {

std::vector<std::size_t> find_steps(const Pipeline& p, const std::string& name) {
    std::vector<std::size_t> by_id, by_stage;
    for (std::size_t i = 0; i < p.steps.size(); ++i) {
        if (p.steps[i].id == name) by_id.push_back(i);
        if (p.steps[i].stage == name) by_stage.push_back(i);
    }
    return by_id.empty() ? by_stage : by_id;
}

std::size_t find_one_step(const Pipeline& p, const std::string& name, const std::string& what) {
    const auto hits = find_steps(p, name);
    std::string ids;
    for (auto& s : p.steps) ids += (ids.empty() ? "" : ", ") + s.id;
    if (hits.empty()) throw Error(what + ": no step '" + name + "' in pipeline '" + p.name + "' (steps: " + ids + ")");
    if (hits.size() > 1)
        throw Error(what + ": '" + name + "' names " + std::to_string(hits.size()) + " steps; use a step id (" + ids + ")");
    return hits.front();
}

const StageVariant& variant_of(const PipelineStep& s) {
    const Registry& reg = registry_of(s);
    return s.variant.empty() ? reg.default_variant(s.stage) : reg.get(s.stage, s.variant);
}

}  // namespace

std::pair<std::string, std::string> split_step_param(const std::string& k) {
    const auto dot = k.find('.');
    return {k.substr(0, dot), dot == std::string::npos ? "" : k.substr(dot + 1)};
}

void set_param(Pipeline& p, const std::string& a) {
    const auto eq = a.find('=');
    if (eq == std::string::npos || a.substr(0, eq).find('.') == std::string::npos)
        throw Error("--set '" + a + "': expected stage.param=value");
    const auto [step, param] = split_step_param(a.substr(0, eq));
    const std::string where = "--set '" + a + "'";
    const double v = Registry::param_value(variant_of(p.steps[find_one_step(p, step, where)]), param, a.substr(eq + 1), where);
    set_param_value(p, step, param, v, where);
}

void set_param_value(Pipeline& p, const std::string& step, const std::string& param, double v, const std::string& source) {
    const std::size_t i = find_one_step(p, step, source);
    Registry::resolve_params(variant_of(p.steps[i]), {{param, v}}, source);
    p.steps[i].params[param] = v;
}

void set_variant(Pipeline& p, const std::string& a) {
    const auto eq = a.find('=');
    if (eq == std::string::npos) throw Error("--variant '" + a + "': expected stage=variant");
    const std::string step = a.substr(0, eq), variant = a.substr(eq + 1);
    const std::size_t i = find_one_step(p, step, "--variant '" + a + "'");
    PipelineStep& s = p.steps[i];
    const StageVariant* v = nullptr;
    try {
        v = &registry_of(s).get(s.stage, variant);
    } catch (const Error& e) {
        throw Error("--variant '" + a + "': " + e.what());
    }
    // Parameters and port bindings the new variant does not declare are dropped (docs/stylize.md).
    for (auto it = s.params.begin(); it != s.params.end();) {
        bool known = false;
        for (auto& d : v->params) known |= d.name == it->first;
        it = known ? std::next(it) : s.params.erase(it);
    }
    for (auto* m : {&s.in, &s.out})
        for (auto it = m->begin(); it != m->end();)
            it = find_port(m == &s.in ? v->inputs : v->outputs, it->first) ? std::next(it) : m->erase(it);
    s.variant = variant;
    Registry::resolve_params(*v, s.params, "--variant '" + a + "'");
}

bool has_image_space_turbulence(const Pipeline& p) {
    return std::any_of(p.steps.begin(), p.steps.end(),
                       [](const PipelineStep& s) { return variant_of(s).image_space_turbulence; });
}

void bypass_step(Pipeline& p, const std::string& step) {
    const std::string what = "--bypass '" + step + "'";
    const std::size_t i = find_one_step(p, step, what);
    const ResolvedStep r = resolve_step(p, i);
    // Output target -> the input target that replaces it.
    std::vector<std::pair<std::string, std::string>> through;
    for (std::size_t k = 0; k < r.variant->outputs.size(); ++k) {
        const std::string& port = r.variant->outputs[k].name;
        const int in = port_index(r.variant->inputs, port);
        if (in < 0) {
            std::string readers;
            for (std::size_t j = i + 1; j < p.steps.size(); ++j) {
                const ResolvedStep rj = resolve_step(p, j);
                if (std::find(rj.inputs.begin(), rj.inputs.end(), r.outputs[k]) != rj.inputs.end())
                    readers += (readers.empty() ? "" : ", ") + p.steps[j].id;
            }
            throw Error(what + ": step '" + p.steps[i].id + "' (" + r.variant->key() + ") writes '" + r.outputs[k] +
                        "' from no input of the same port ('" + port + "'), so nothing can pass through it" +
                        (readers.empty() ? std::string() : "; bypass the step that reads it instead (" + readers + ")"));
        }
        through.emplace_back(r.outputs[k], r.inputs[std::size_t(in)]);
    }
    // Each target has one writer (validate_pipeline), so every reader of `from` reads the bypassed step's.
    for (std::size_t j = i + 1; j < p.steps.size(); ++j) {
        const ResolvedStep rj = resolve_step(p, j);
        for (std::size_t k = 0; k < rj.inputs.size(); ++k)
            for (auto& [from, to] : through)
                if (rj.inputs[k] == from) p.steps[j].in[rj.variant->inputs[k].name] = to;
    }
    for (auto& [from, to] : through)
        if (p.output == from) p.output = to;
    p.steps.erase(p.steps.begin() + std::ptrdiff_t(i));
}

ResolvedStep resolve_step(const Pipeline& p, std::size_t i) {
    const PipelineStep& s = p.steps.at(i);
    const std::string key = p.source + ": " + idx("steps", i);
    ResolvedStep r;
    try {
        r.variant = &variant_of(s);
    } catch (const Error& e) {
        throw Error(key + ": " + e.what());
    }
    r.params = Registry::resolve_params(*r.variant, s.params, key + ".params");
    if (r.variant->validate) {
        try {
            r.variant->validate(r.params);
        } catch (const Error& e) {
            throw Error(key + ".params (" + r.variant->key() + "): " + e.what());
        }
    }
    r.step = r.variant->bound(r.params);
    for (auto& [port, t] : s.in)
        if (!find_port(r.variant->inputs, port)) throw Error(key + ".in." + port + ": unknown input port of " + r.variant->key());
    for (auto& [port, t] : s.out)
        if (!find_port(r.variant->outputs, port)) throw Error(key + ".out." + port + ": unknown output port of " + r.variant->key());
    for (auto& port : r.variant->inputs) {
        auto it = s.in.find(port.name);
        r.inputs.push_back(it != s.in.end() ? it->second : port.default_target);
    }
    for (auto& port : r.variant->outputs) {
        auto it = s.out.find(port.name);
        r.outputs.push_back(it != s.out.end() ? it->second : port.default_target);
    }
    r.pass = s.pass;
    r.label = s.id + " (" + r.variant->key() + ")";
    r.where = key + " (" + r.variant->key() + ")";
    return r;
}

CompiledPipeline compile_pipeline(const Pipeline& p, const Targets* gbuffer) {
    CompiledPipeline c;
    c.name = p.name;
    c.source = p.source;
    c.output = p.output;
    c.substrate_color = p.substrate_color;
    c.paper = p.paper;
    c.has_paper = p.has_paper;
    c.foliage = p.foliage;
    c.has_foliage = p.has_foliage;
    std::map<std::string, int> produced;  // target -> channels
    std::map<std::string, std::string> producer;
    std::map<std::string, std::size_t> external_index;
    for (std::size_t i = 0; i < p.steps.size(); ++i) {
        CompiledStep r = resolve_step(p, i);
        const std::string& key = r.where;
        for (std::size_t k = 0; k < r.inputs.size(); ++k) {
            const Port& port = r.variant->inputs[k];
            const std::string& t = r.inputs[k];
            c.last_read[t] = i;
            int ch = -1;
            if (auto it = produced.find(t); it != produced.end()) {
                ch = it->second;
            } else if (t == kPaperTarget) {
                ch = 3;
            } else if (auto e = external_index.find(t); e != external_index.end()) {
                ExternalInput& x = c.external[e->second];
                x.optional = x.optional && port.optional;
                if (port.channels != x.channels)
                    throw Error(key + ": input '" + port.name + "' needs " + std::to_string(port.channels) +
                                " channels but target '" + t + "' is read with " + std::to_string(x.channels) +
                                " by " + x.reader);
            } else {
                external_index[t] = c.external.size();
                c.external.push_back({t, port.channels, port.optional, key, port.name});
            }
            if (ch >= 0 && ch != port.channels)
                throw Error(key + ": input '" + port.name + "' needs " + std::to_string(port.channels) +
                            " channels but target '" + t + "' has " + std::to_string(ch));
        }
        for (std::size_t k = 0; k < r.outputs.size(); ++k) {
            const std::string& t = r.outputs[k];
            if (std::find(r.inputs.begin(), r.inputs.end(), t) != r.inputs.end())
                throw Error(key + ": output '" + r.variant->outputs[k].name + "' writes its own input '" + t + "'");
            if (produced.count(t))
                throw Error(key + ": output '" + r.variant->outputs[k].name + "' writes target '" + t +
                            "', already written by " + producer[t]);
            if (t == kPaperTarget || external_index.count(t))
                throw Error(key + ": output '" + r.variant->outputs[k].name + "' would overwrite input target '" + t + "'");
            for (std::size_t m = 0; m < k; ++m)
                if (r.outputs[m] == t) throw Error(key + ": two outputs write target '" + t + "'");
            produced[t] = r.variant->outputs[k].channels;
            producer[t] = idx("steps", i);
            c.produced.push_back(t);
        }
        c.has_passes = c.has_passes || r.pass;
        c.steps.push_back(std::move(r));
    }
    if (!produced.count(p.output) && !external_index.count(p.output))
        c.external.push_back({p.output, 0, false, p.source + ": output", ""});
    schedule::plan(c);
    if (gbuffer) check_gbuffer(c, *gbuffer);
    return c;
}

namespace {
//! check_gbuffer, with `kept` the outputs of steps a run from RunOptions::first_step does not run.
void check_gbuffer_except(const CompiledPipeline& c, const Targets& gbuffer, const std::set<std::string>& kept) {
    const ImageF* first = nullptr;
    std::string first_name;
    for (const ExternalInput& x : c.external) {
        if (!gbuffer.has(x.target)) {
            if (x.optional) continue;
            if (x.port.empty()) throw Error(x.reader + ": target '" + x.target + "' is not written by any step");
            throw Error(x.reader + ": input '" + x.port + "' reads target '" + x.target +
                        "', which no earlier step writes and the G-buffer does not have");
        }
        const ImageF& img = gbuffer.get(x.target);
        if (x.port.empty()) continue;  // the output, taken from the G-buffer as it is
        if (img.channels() != x.channels)
            throw Error(x.reader + ": input '" + x.port + "' needs " + std::to_string(x.channels) +
                        " channels but target '" + x.target + "' has " + std::to_string(img.channels()));
        if (!first) {
            first = &img;
            first_name = x.target;
        } else if (!img.same_size(*first)) {
            throw Error(x.reader + ": G-buffer target '" + x.target + "' is " + std::to_string(img.width()) + "x" +
                        std::to_string(img.height()) + " but '" + first_name + "' is " +
                        std::to_string(first->width()) + "x" + std::to_string(first->height()));
        }
    }
    for (const std::string& t : c.produced)
        if (gbuffer.has(t) && !kept.count(t))
            throw Error(c.source + ": target '" + t + "' is written by a step but already present (a G-buffer target "
                        "cannot be overwritten; a frame loop passes RunOptions::reuse_outputs)");
}
}  // namespace

void check_gbuffer(const CompiledPipeline& c, const Targets& gbuffer) { check_gbuffer_except(c, gbuffer, {}); }

void validate_pipeline(const Pipeline& p, const Targets* gbuffer) { (void)compile_pipeline(p, gbuffer); }

void run_pipeline(const Pipeline& p, Targets& targets, const RunOptions& opt) {
    run_pipeline(compile_pipeline(p), targets, opt);
}

namespace {

//! The check after a step: every output exists with its port's channel count.
void check_output(const CompiledStep& r, std::size_t k, const ImageF& o) {
    if (o.empty() || o.channels() != r.variant->outputs[k].channels)
        throw Error(r.where + ": stage did not produce output '" + r.variant->outputs[k].name + "' with " +
                    std::to_string(r.variant->outputs[k].channels) + " channels");
}

//! Runs the steps of a row group band by band (RowGroup); their outputs end in `targets` as if
//! each step had run alone. `recycled`: the previous frame's outputs (RunOptions::reuse_outputs).
void run_row_group(const CompiledPipeline& c, const RowGroup& gr, Targets& targets, const Globals& g,
                   const RunOptions& opt, std::map<std::string, ImageF>& recycled, bool in_place) {
    const std::size_t n = gr.last - gr.first + 1;
    std::vector<std::vector<ImageF>> outs(n);
    std::vector<StageIO> io(n);
    std::map<std::string, ImageF*> live;  // outputs of the group's steps
    std::set<std::string> consumed;       // of those, computed over in place by a later step
    for (std::size_t j = 0; j < n; ++j) {
        const CompiledStep& r = c.steps[gr.first + j];
        io[j].globals = &g;
        for (const std::string& t : r.inputs) {
            const auto it = live.find(t);
            io[j].in.push_back(it != live.end() ? it->second : targets.has(t) ? &targets.get(t) : nullptr);
        }
        outs[j].resize(r.outputs.size());
        for (std::size_t k = 0; k < outs[j].size(); ++k)
            if (auto it = recycled.find(r.outputs[k]); it != recycled.end()) outs[j][k] = std::move(it->second);
        for (auto& o : outs[j]) io[j].out.push_back(&o);
        if (const int k = in_place ? c.in_place[gr.first + j] : -1; k >= 0) {
            // The dead input's image becomes the output (as step by step): the group's own image
            // when an earlier step of the group writes it.
            const std::string& t = r.inputs[std::size_t(k)];
            const std::size_t ko = std::size_t(port_index(r.variant->outputs, r.variant->in_place_output));
            if (auto it = live.find(t); it != live.end()) {
                io[j].out[ko] = it->second;
                consumed.insert(t);
            } else {
                const ImageF* was = &targets.get(t);
                outs[j][ko] = std::move(targets.get_mut(t));
                targets.erase(t);
                for (std::size_t q = 0; q < j; ++q)  // earlier steps of the group that read it
                    for (const ImageF*& in : io[q].in)
                        if (in == was) in = &outs[j][ko];
            }
            io[j].in[std::size_t(k)] = io[j].out[ko];
        }
        for (std::size_t k = 0; k < r.outputs.size(); ++k) live[r.outputs[k]] = io[j].out[k];
    }
    auto run = [&](std::size_t j, int y0, int y1) {
        const CompiledStep& r = c.steps[gr.first + j];
        try {
            r.step(io[j], opt.exec.rows(y0, y1));
        } catch (const Error& e) {
            throw Error(r.where + ": " + e.what());
        }
    };
    // Checks and allocations in step order (an empty window): the errors of step by step.
    int W = -1, H = -1;
    bool same_size = true;
    for (std::size_t j = 0; j < n; ++j) {
        run(j, 0, 0);
        const CompiledStep& r = c.steps[gr.first + j];
        for (std::size_t k = 0; k < r.outputs.size(); ++k) {
            const ImageF& o = *io[j].out[k];
            check_output(r, k, o);
            if (W < 0) W = o.width(), H = o.height();
            same_size = same_size && o.width() == W && o.height() == H;
        }
    }
    if (!same_size) {  // outputs of several sizes (not from the built-in variants): step by step
        for (std::size_t j = 0; j < n; ++j) run(j, 0, INT_MAX);
    } else {
        schedule::run_bands(H, gr.depth, gr.max_depth, opt.band_rows, opt.exec, run);
    }
    for (std::size_t j = 0; j < n; ++j) {
        const CompiledStep& r = c.steps[gr.first + j];
        for (std::size_t k = 0; k < r.outputs.size(); ++k)
            if (!consumed.count(r.outputs[k])) targets.set(r.outputs[k], std::move(*io[j].out[k]));
    }
}

}  // namespace

namespace {

//! The outputs of the steps before opt.first_step: inputs of this run, which must be in targets
//! (a live run continuing an earlier one, with fuse, in_place, row_groups and release_dead off).
std::set<std::string> kept_outputs(const CompiledPipeline& c, const Targets& targets, const RunOptions& opt) {
    const int first = opt.first_step;
    if (first < 0 || first > int(c.steps.size())) throw Error(c.source + ": first step " + std::to_string(first) + " out of range");
    std::set<std::string> kept;
    for (int i = 0; i < first; ++i)
        for (const std::string& t : c.steps[std::size_t(i)].outputs) kept.insert(t);
    if (first > 0) {
        if (opt.fuse || opt.in_place || opt.row_groups || opt.release_dead)
            throw Error(c.source + ": a run from step " + std::to_string(first) + " needs fuse, in_place, row_groups and release_dead off");
        for (const std::string& t : kept)
            if (!targets.has(t)) throw Error(c.source + ": a run from step " + std::to_string(first) + " needs '" + t + "' from an earlier run");
    }
    return kept;
}

//! The image size of the run: the first G-buffer target read (check_gbuffer checked they agree),
//! else the scene's; the paper prepared at that size; with release_inputs, the G-buffer targets no
//! step reads released.
void prepare_run_targets(const CompiledPipeline& c, Targets& targets, const RunOptions& opt) {
    int w = 0, h = 0;
    for (const ExternalInput& x : c.external)
        if (!x.port.empty() && targets.has(x.target)) {
            w = targets.get(x.target).width();
            h = targets.get(x.target).height();
            break;
        }
    if (w == 0 && opt.scene) {
        w = opt.scene->width;
        h = opt.scene->height;
    }
    if (c.has_passes && !opt.scene)
        throw Error(c.source + ": the pipeline has raster passes, which need a scene (aquarelle render)");
    if (w == 0) throw Error(c.source + ": no step reads a G-buffer target");
    if (!targets.has(kPaperTarget))
        targets.set(kPaperTarget, c.has_paper ? prepare_paper(c.paper, w, h, opt.exec) : flat_paper(w, h));
    if (opt.release_dead && opt.release_inputs) {
        clear_paper_cache();  // the decoded source is not needed again
        for (const std::string& t : targets.names())
            if (t != kPaperTarget && t != c.output && !c.last_read.count(t) &&
                std::find(c.produced.begin(), c.produced.end(), t) == c.produced.end())
                targets.erase(t);  // a G-buffer target no step reads
    }
}

//! Releases the intermediates and G-buffer targets whose last reader is step i (`fused`: i ran with
//! i - 1, so what the producer read last dies here too).
void release_after(const CompiledPipeline& c, Targets& targets, const RunOptions& opt, int i, const Fusion* fused) {
    const CompiledStep& r = c.steps[std::size_t(i)];
    auto read_last_here = [&](std::size_t at) { return at == std::size_t(i) || (fused && at + 1 == std::size_t(i)); };
    for (const std::string& t : c.produced) {
        if (t == c.output || !targets.has(t)) continue;
        const auto last = c.last_read.find(t);
        const bool dead = last == c.last_read.end() ? std::find(r.outputs.begin(), r.outputs.end(), t) != r.outputs.end()
                                                    : read_last_here(last->second);
        if (dead) targets.erase(t);
    }
    if (opt.release_inputs)
        for (const ExternalInput& x : c.external)
            if (x.target != c.output && x.target != kPaperTarget && targets.has(x.target) && read_last_here(c.last_read.at(x.target)))
                targets.erase(x.target);
}

std::vector<const ImageF*> inputs_of(const CompiledStep& r, const Targets& targets) {
    std::vector<const ImageF*> in;
    for (const std::string& t : r.inputs) in.push_back(targets.has(t) ? &targets.get(t) : nullptr);
    return in;
}

//! Step i alone (or with its fused producer i - 1): outputs from `recycled` where kept from the
//! previous frame, the dead input's image as the output of an in-place step.
void run_step(const CompiledPipeline& c, int i, const Fusion* fused, Targets& targets, const Globals& g, const RunOptions& opt,
              std::map<std::string, ImageF>& recycled, bool in_place) {
    const CompiledStep& r = c.steps[std::size_t(i)];
    StageIO io;
    io.globals = &g;
    io.in = inputs_of(r, targets);
    std::vector<ImageF> outs(r.outputs.size());
    for (std::size_t k = 0; k < outs.size(); ++k)
        if (auto it = recycled.find(r.outputs[k]); it != recycled.end()) outs[k] = std::move(it->second);
    for (auto& o : outs) io.out.push_back(&o);
    if (const int k = in_place ? c.in_place[std::size_t(i)] : -1; k >= 0) {
        // The dead input's image becomes the output; the stage writes what changes.
        const std::string& t = r.inputs[std::size_t(k)];
        ImageF& o = outs[std::size_t(port_index(r.variant->outputs, r.variant->in_place_output))];
        o = std::move(targets.get_mut(t));
        targets.erase(t);
        io.in[std::size_t(k)] = &o;
    }
    try {
        if (fused) {
            const CompiledStep& pr = c.steps[std::size_t(i) - 1];
            StageIO pio;
            pio.globals = &g;
            pio.in = inputs_of(pr, targets);
            for (const auto& link : fused->links) io.in[std::size_t(port_index(r.variant->inputs, link.second))] = nullptr;
            fused->run(pio, pr.params, io, r.params, opt.exec);
        } else {
            r.step(io, opt.exec);
        }
    } catch (const Error& e) {
        throw Error(r.where + ": " + e.what());
    }
    for (std::size_t k = 0; k < outs.size(); ++k) {
        check_output(r, k, outs[k]);
        targets.set(r.outputs[k], std::move(outs[k]));
    }
}

double ms_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

void run_pipeline(const CompiledPipeline& c, Targets& targets, const RunOptions& opt) {
    const int first = opt.first_step;
    const std::set<std::string> kept = kept_outputs(c, targets, opt);
    std::map<std::string, ImageF> recycled;
    if (opt.reuse_outputs)
        for (const std::string& t : c.produced)
            if (targets.has(t) && !kept.count(t)) {
                recycled[t] = std::move(targets.get_mut(t));
                targets.erase(t);
            }
    check_gbuffer_except(c, targets, kept);
    prepare_run_targets(c, targets, opt);
    Globals g;
    g.substrate_color = c.substrate_color;
    g.paper = &targets.get(kPaperTarget);
    g.scene = opt.scene;
    g.warnings = opt.warnings;
    const int n = int(c.steps.size());
    if (opt.step_ms) opt.step_ms->assign(std::size_t(n), 0.0);
    const bool fuse = opt.fuse && c.fused_with_next.size() == c.steps.size();
    const bool in_place = opt.in_place && c.in_place.size() == c.steps.size();
    std::map<int, const RowGroup*> group_at;  // first step -> its row group
    if (opt.row_groups && opt.exec.traversal == Traversal::Fast)
        for (const RowGroup& gr : c.row_groups) group_at[int(gr.first)] = &gr;
    for (int i = first; i < n; ++i) {
        if (const auto grp = group_at.find(i); grp != group_at.end()) {
            const RowGroup& gr = *grp->second;
            for (std::size_t s = gr.first; s <= gr.last; ++s)
                if (opt.progress) opt.progress(int(s), n, c.steps[s].label);
            const auto t0 = std::chrono::steady_clock::now();
            run_row_group(c, gr, targets, g, opt, recycled, in_place);
            if (opt.step_ms) (*opt.step_ms)[gr.last] = ms_since(t0);  // the group's time is its last step's
            if (opt.release_dead)
                for (std::size_t s = gr.first; s <= gr.last; ++s) release_after(c, targets, opt, int(s), nullptr);
            i = int(gr.last);
            continue;
        }
        if (opt.progress) opt.progress(i, n, c.steps[std::size_t(i)].label);
        if (fuse && c.fused_with_next[std::size_t(i)]) continue;  // runs with step i + 1
        const Fusion* fused = fuse && i > 0 ? c.fused_with_next[std::size_t(i) - 1] : nullptr;
        const auto t0 = std::chrono::steady_clock::now();
        run_step(c, i, fused, targets, g, opt, recycled, in_place);
        if (opt.step_ms) (*opt.step_ms)[std::size_t(i)] = ms_since(t0);
        if (opt.release_dead) release_after(c, targets, opt, i, fused);
    }
}

}  // namespace aq::stylize
