// reference/stage_twin.cpp — directive parsing and pass scheduling for the stage twins.
#include "reference/stage_twin.h"

#include <functional>
#include <map>
#include <sstream>

namespace aq::ref {

namespace {

std::string ident(const std::string& s) {
    std::string r = s;
    for (char& c : r)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) c = '_';
    return r;
}

std::vector<std::string> split(const std::string& s, char sep) {
    std::vector<std::string> out;
    std::string cur;
    std::istringstream in(s);
    while (std::getline(in, cur, sep))
        if (!cur.empty()) out.push_back(cur);
    return out;
}

}  // namespace

std::string twin_file(const stylize::StageVariant& v) { return v.stage + "." + v.variant + ".glsl"; }
bool has_twin(const stylize::StageVariant& v) { return shader_file_exists(twin_file(v)); }

std::string param_uniform_decls(const std::vector<stylize::ParamDesc>& params) {
    std::string s;
    for (auto& p : params) {
        const char* t = p.kind == stylize::ParamKind::Float ? "float" : p.kind == stylize::ParamKind::Int ? "int" : "bool";
        s += std::string("uniform ") + t + " u_" + ident(p.name) + ";\n";
    }
    return s;
}

StageTwin::StageTwin(const stylize::StageVariant& v) : v_(&v) {
    const std::string file = twin_file(v);
    // //@include <file> lines are replaced by that file (shared bodies of related variants), which
    // may include further files (at most kMaxIncludeDepth levels: a cycle is an error).
    {
        constexpr int kMaxIncludeDepth = 4;
        std::function<void(const std::string&, int)> expand = [&](const std::string& name, int depth) {
            if (depth > kMaxIncludeDepth) throw Error(file + ": //@include nested deeper than 4 (a cycle?) at " + name);
            std::istringstream raw(load_shader_file(name));
            std::string l;
            while (std::getline(raw, l)) {
                if (l.rfind("//@include ", 0) == 0) expand(l.substr(11), depth + 1);
                else source_ += l + "\n";
            }
        };
        expand(file, 0);
    }
    std::map<std::string, std::string> outputs;
    std::istringstream in(source_);
    std::string line;
    auto known_input = [&](const std::string& n) {
        if (n == "paper") return true;
        for (auto& p : v.inputs)
            if (p.name == n) return true;
        for (auto& p : passes_)
            if (p.name == n) return true;
        return false;
    };
    for (int ln = 1; std::getline(in, line); ++ln) {
        const std::string where = file + ":" + std::to_string(ln) + ": ";
        if (line.rfind("//@pass ", 0) == 0) {
            auto words = split(line.substr(8), ' ');
            if (words.empty()) throw Error(where + "@pass needs a name");
            PassDecl p;
            p.name = words[0];
            for (std::size_t k = 1; k < words.size(); ++k) {
                const auto eq = words[k].find('=');
                if (eq == std::string::npos) throw Error(where + "expected key=value, got '" + words[k] + "'");
                const std::string key = words[k].substr(0, eq), val = words[k].substr(eq + 1);
                if (key == "out") {
                    p.channels = std::stoi(val);
                } else if (key == "size") {
                    const auto colon = val.find(':');
                    const std::string mode = colon == std::string::npos ? "" : val.substr(0, colon);
                    p.size_of = colon == std::string::npos ? val : val.substr(colon + 1);
                    // The parameter a size mode names: it must exist, of that kind.
                    auto param = [&](const std::string& name, stylize::ParamKind kind) {
                        for (auto& d : v.params)
                            if (d.name == name && d.kind == kind) return name;
                        throw Error(where + "size=" + val + " names no parameter '" + name + "' of the kind it needs");
                    };
                    if (mode == "half") {
                        p.half = true;
                    } else if (mode.rfind("half_if_", 0) == 0) {
                        p.half_param = param(mode.substr(8), stylize::ParamKind::Bool);
                    } else if (mode.rfind("div_", 0) == 0) {
                        p.div_param = param(mode.substr(4), stylize::ParamKind::Int);
                    } else if (!mode.empty()) {
                        throw Error(where + "unknown size mode '" + mode + "'");
                    }
                    if (!known_input(p.size_of)) throw Error(where + "size= names unknown input '" + p.size_of + "'");
                } else if (key == "in") {
                    for (auto& spec : split(val, ',')) {
                        auto parts = split(spec, ':');
                        In i;
                        i.name = parts[0];
                        i.ident = ident(parts[0]);
                        for (std::size_t m = 1; m < parts.size(); ++m) {
                            if (parts[m] == "linear") i.filter = Filter::Linear;
                            else if (parts[m] == "mirror") i.wrap = Wrap::Mirror;
                            else throw Error(where + "unknown input modifier '" + parts[m] + "'");
                        }
                        if (!known_input(i.name))
                            throw Error(where + "input '" + i.name + "' is neither a port of " + v.key() +
                                        ", an earlier pass nor 'paper'");
                        p.inputs.push_back(i);
                    }
                } else {
                    throw Error(where + "unknown @pass key '" + key + "'");
                }
            }
            if (p.size_of.empty()) {
                if (p.inputs.empty()) throw Error(where + "pass without inputs needs size=");
                p.size_of = p.inputs.front().name;
            }
            passes_.push_back(p);
        } else if (line.rfind("//@output ", 0) == 0) {
            const std::string rest = line.substr(10);
            const auto eq = rest.find('=');
            if (eq == std::string::npos) throw Error(where + "@output needs port=pass");
            outputs[rest.substr(0, eq)] = rest.substr(eq + 1);
        }
    }
    if (passes_.empty()) throw Error(file + ": no //@pass directive");
    for (auto& o : v.outputs) {
        auto it = outputs.find(o.name);
        if (it == outputs.end()) {
            if (v.outputs.size() != 1) throw Error(file + ": no //@output line for output '" + o.name + "'");
            output_pass_.push_back(passes_.back().name);
        } else {
            bool found = false;
            for (auto& p : passes_) found |= p.name == it->second;
            if (!found) throw Error(file + ": @output " + o.name + " names unknown pass '" + it->second + "'");
            output_pass_.push_back(it->second);
        }
    }
}

std::vector<Texture> StageTwin::run(const std::vector<const Texture*>& inputs, const stylize::ParamValues& params,
                                    const glm::vec3& substrate_color, const Texture* paper) const {
    const auto& v = *v_;
    if (inputs.size() != v.inputs.size())
        throw Error(v.key() + " twin: " + std::to_string(inputs.size()) + " inputs given, " +
                    std::to_string(v.inputs.size()) + " declared");
    std::map<std::string, const Texture*> avail;
    for (std::size_t k = 0; k < inputs.size(); ++k) avail[v.inputs[k].name] = inputs[k];
    avail["paper"] = paper;
    std::map<std::string, Texture> produced;
    const std::string uniforms = param_uniform_decls(v.params);
    for (auto& pd : passes_) {
        std::vector<std::string> defines = {"PASS_" + pd.name + " 1"};
        Pass pass;
        pass.name = v.key() + "/" + pd.name;
        for (auto& i : pd.inputs) {
            const Texture* t = nullptr;
            if (auto it = produced.find(i.name); it != produced.end()) t = &it->second;
            else t = avail[i.name];
            defines.push_back("HAS_" + i.ident + (t ? " 1" : " 0"));
            if (t) pass.inputs["s_" + i.ident] = {t, i.filter, i.wrap};
        }
        const Texture* sz = nullptr;
        if (auto it = produced.find(pd.size_of); it != produced.end()) sz = &it->second;
        else sz = avail[pd.size_of];
        if (!sz) throw Error(pass.name + ": size input '" + pd.size_of + "' is absent");
        const bool half = pd.half || (!pd.half_param.empty() && params.at(pd.half_param) != 0.0);
        const int div = half ? 2 : pd.div_param.empty() ? 1 : int(params.at(pd.div_param));
        pass.width = (sz->width() + div - 1) / div;
        pass.height = (sz->height() + div - 1) / div;
        pass.channels = pd.channels;
        std::string body = uniforms;
        for (auto& i : pd.inputs) body += "uniform sampler2D s_" + i.ident + ";\n";
        body += "#line 1 3\n" + source_;
        pass.fragment = assemble_fragment(body, defines);
        for (auto& d : v.params) {
            const double x = params.at(d.name);
            const std::string n = "u_" + ident(d.name);
            if (d.kind == stylize::ParamKind::Float) pass.uniforms[n] = float(x);
            else if (d.kind == stylize::ParamKind::Int) pass.uniforms[n] = int(x);
            else pass.uniforms[n] = x != 0.0;
        }
        pass.uniforms["u_substrate_color"] = substrate_color;
        produced[pd.name] = run_pass_texture(pass);
    }
    std::vector<Texture> outs;
    for (auto& name : output_pass_) {
        // An output may be bound twice (rare); move the first, copy-free re-run is not needed.
        outs.push_back(std::move(produced.at(name)));
    }
    return outs;
}

std::vector<ImageF> StageTwin::run(const std::vector<const ImageF*>& inputs, const stylize::ParamValues& params,
                                   const stylize::Globals& globals) const {
    std::vector<Texture> up;
    up.reserve(inputs.size());
    std::vector<const Texture*> ptrs;
    for (auto* img : inputs) {
        up.push_back(img ? Texture::upload(*img) : Texture());
        ptrs.push_back(img ? &up.back() : nullptr);
    }
    Texture paper = globals.paper ? Texture::upload(*globals.paper) : Texture();
    auto outs = run(ptrs, params, globals.substrate_color, globals.paper ? &paper : nullptr);
    std::vector<ImageF> imgs;
    for (auto& t : outs) imgs.push_back(read_texture(t));
    return imgs;
}

}  // namespace aq::ref
