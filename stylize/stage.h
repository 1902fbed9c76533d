// stylize/stage.h — the stage registry: every image-space effect, every published variant, by name.
//
// A stage variant is data: {stage, variant, ports it reads and writes, parameter table, run}.
// Tests, benchmarks, the CLI and pipeline files all find variants here by name (conventions.md:
// "variants are registered, not copy-pasted"). The per-pixel maths lives in typed functions in
// stylize/stages/*.h; the registry entry only adapts them to named targets and parameter maps.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <tuple>
#include <type_traits>
#include <vector>

#include <glm/glm.hpp>

#include "core/exec.h"
#include "core/image.h"
#include "core/targets.h"

namespace aq::raster {
struct PassScene;  // raster/pass.h: only the pass registry's steps (stylize/passes/) read it
}

namespace aq::stylize {

// ---------------------------------------------------------------------------------------------
// Parameters: a struct with defaults (the stage's typed API) plus a table of names and ranges.

enum class ParamKind { Float, Int, Bool };

struct ParamDesc {
    std::string name;
    ParamKind kind = ParamKind::Float;
    double def = 0, lo = 0, hi = 1;
    std::string doc;
    //! An Int parameter with named values (value k is names[k], range 0..n-1): pipeline files,
    //! --set and the Python module take the name or the number. Empty: a plain number.
    std::vector<std::string> names = {};
};

//! The parameter called `name` in `params`, or null (names are unique within a variant).
const ParamDesc* find_param(const std::vector<ParamDesc>& params, const std::string& name);
//! "float", "int" or "bool": the kind's name in listings, the live page's schema and Python.
const char* param_kind_name(ParamKind k);

//! Complete, validated parameter values of one stage instance (every declared name present).
using ParamValues = std::map<std::string, double>;

//! A field inside nested members and arrays of a parameter struct: each step a member pointer or
//! an index. field_path(&ShadowLayerParams::wash, &LayerWashParams::shape, &WashShape::kappa) names
//! p.wash.shape.kappa; field_path(&ColorRampParams::layer, 2, &ColorRampLayer::color, 0) names
//! p.layer[2].color[0].
template <class... M>
struct FieldPath {
    std::tuple<M...> steps;
};
template <class... M>
FieldPath<M...> field_path(M... steps) {
    return {{steps...}};
}
namespace detail {
template <class X, class M, class... Rest>
decltype(auto) walk_field(X& x, M m, Rest... rest) {
    auto& next = [&]() -> auto& {
        if constexpr (std::is_member_object_pointer_v<M>)
            return x.*m;
        else
            return x[m];
    }();
    if constexpr (sizeof...(Rest) == 0)
        return (next);
    else
        return walk_field(next, rest...);
}
}  // namespace detail
//! The field `m` of p: a member pointer or a FieldPath.
template <class P, class M>
decltype(auto) field_of(P& p, M m) {
    if constexpr (std::is_member_object_pointer_v<M>)
        return (p.*m);
    else
        return std::apply([&p](auto... ms) -> decltype(auto) { return detail::walk_field(p, ms...); }, m.steps);
}

//! Binds the fields of a parameter struct P (each a member pointer or a FieldPath) to names and
//! ranges; the struct's own default is the parameter's.
template <class P>
class ParamTable {
public:
    template <class M>
    ParamTable& f(std::string name, M m, double lo, double hi, std::string doc) {
        return field<float, M>({std::move(name), ParamKind::Float, 0, lo, hi, std::move(doc)}, m);
    }
    template <class M>
    ParamTable& i(std::string name, M m, int lo, int hi, std::string doc) {
        using T = std::remove_cvref_t<decltype(field_of(std::declval<P&>(), m))>;
        static_assert(std::is_integral_v<T> && !std::is_same_v<T, bool>, "an int parameter is an integer field");
        return field<T, M>({std::move(name), ParamKind::Int, 0, double(lo), double(hi), std::move(doc)}, m);
    }
    //! An enum-like field (an int, or an enum with values 0..n-1): value k is names[k].
    template <class M>
    ParamTable& e(std::string name, M m, std::vector<std::string> names, std::string doc) {
        const double hi = double(names.size()) - 1.0;
        using T = std::remove_cvref_t<decltype(field_of(std::declval<P&>(), m))>;
        static_assert(std::is_enum_v<T> || std::is_same_v<T, int>, "an enum parameter is an int or an enum");
        return field<T, M>({std::move(name), ParamKind::Int, 0, 0.0, hi, std::move(doc), std::move(names)}, m);
    }
    //! The rule for taps outside the image (core/image.h Border), named `border` in every stage.
    template <class M>
    ParamTable& border(M m) {
        return e("border", m, {"clamp", "mirror"}, "taps outside the image: clamp to the edge or mirror");
    }
    template <class M>
    ParamTable& b(std::string name, M m, std::string doc) {
        return field<bool, M>({std::move(name), ParamKind::Bool, 0, 0.0, 1.0, std::move(doc)}, m);
    }
    const std::vector<ParamDesc>& descs() const { return descs_; }
    //! Values must already be validated (see Registry::resolve_params).
    P from(const ParamValues& v) const {
        P p{};
        for (std::size_t k = 0; k < descs_.size(); ++k) {
            auto it = v.find(descs_[k].name);
            if (it != v.end()) setters_[k](p, it->second);
        }
        return p;
    }

private:
    //! Field m of type T (checked), its default read from P{}.
    template <class T, class M>
    ParamTable& field(ParamDesc d, M m) {
        static_assert(std::is_same_v<std::remove_cvref_t<decltype(field_of(std::declval<P&>(), m))>, T>,
                      "the field's type does not match the parameter kind");
        P defaults{};
        if constexpr (std::is_enum_v<T>)
            d.def = double(int(field_of(defaults, m)));
        else
            d.def = double(field_of(defaults, m));
        descs_.push_back(std::move(d));
        setters_.push_back([m](P& p, double v) {
            if constexpr (std::is_same_v<T, bool>)
                field_of(p, m) = v != 0.0;
            else if constexpr (std::is_enum_v<T>)
                field_of(p, m) = T(int(v));
            else
                field_of(p, m) = T(v);
        });
        return *this;
    }
    std::vector<ParamDesc> descs_;
    std::vector<std::function<void(P&, double)>> setters_;
};

// ---------------------------------------------------------------------------------------------
// Pipeline-wide values every stage may read (paper colour, paper texture).

struct Globals {
    glm::vec3 substrate_color{1.0f, 1.0f, 1.0f};  //!< paper colour Cp (spec: default white)
    //! Paper texture prepared for this image size: RGB = (normal.x, normal.y) in [0,1] 0.5-centred,
    //! height in B (MNPR layout), tiled one texel per pixel at scale 1. Empty when no paper is set.
    const ImageF* paper = nullptr;
    //! The scene for raster passes (builtin_pass_registry); null when a pipeline runs on images
    //! alone (a pass then refuses to run).
    const raster::PassScene* scene = nullptr;
    //! Non-fatal problems a step reports (a pass that draws nothing); may be null.
    std::vector<std::string>* warnings = nullptr;
    //! paper_height_spread(*paper), computed by the first stage that asks (paper_spread_of) and
    //! kept for the run: the paper does not change while a pipeline runs. Negative: not yet.
    mutable float paper_spread = -1.0f;
};

// ---------------------------------------------------------------------------------------------
// Ports: the logical inputs and outputs of a stage, bound to target names by the pipeline.

//! How an input's size relates to another input's: the port's resolution relation, checked with
//! its channel count before the stage runs (check_io).
enum class SizeRule {
    Any,         //!< no relation (the stage resamples the input, or the input sets the size)
    Same,        //!< the size of input `like`
    FullOrHalf,  //!< the size of `like`, or half of it (ceil(w/2) x ceil(h/2), the WC17 intermediates)
};

struct Port {
    std::string name;            //!< logical name used in pipeline files ("color", "edges", ...)
    std::string default_target;  //!< target name used when the pipeline does not bind the port
    int channels = 4;            //!< required channel count
    bool optional = false;       //!< inputs only: may be absent (stage documents its fallback)
    SizeRule size = SizeRule::Any;  //!< inputs only: the size relation to input `like`
    std::string like = {};          //!< inputs only: the input `size` refers to (empty for Any)
};

//! The port called `name` in `ports`, or null.
const Port* find_port(const std::vector<Port>& ports, const std::string& name);
//! The index of the port called `name` in `ports` (find_port), or -1.
int port_index(const std::vector<Port>& ports, const std::string& name);

//! What a stage sees when it runs: resolved inputs (nullptr for an absent optional input) and the
//! outputs it must fill (it allocates them, choosing their size, e.g. half resolution).
struct StageIO {
    std::vector<const ImageF*> in;
    std::vector<ImageF*> out;
    const Globals* globals = nullptr;
};

using RunFn = std::function<void(StageIO& io, const ParamValues& params, const Exec& ex)>;
//! A run with its parameter values bound (converted to the stage's typed struct once).
using StepFn = std::function<void(StageIO& io, const Exec& ex)>;

class SceneInputs;  // stylize/scene_inputs.h
//! A parameter value a step takes from the scene being rendered, and where it came from (named
//! when the value is out of range).
struct SceneValue {
    std::string param;
    double value = 0;
    std::string source;
};
//! The values a variant takes from the scene, given its resolved parameters.
using SceneParamsFn = std::function<std::vector<SceneValue>(const ParamValues& params, const SceneInputs& scene)>;

struct StageVariant {
    std::string stage = {};    //!< e.g. "bleed"
    std::string variant = {};  //!< e.g. "joint_bilateral"
    std::string doc = {};      //!< one line, with the paper and equation it implements
    std::vector<Port> inputs = {};
    std::vector<Port> outputs = {};
    std::vector<ParamDesc> params = {};
    RunFn run = {};
    //! What Traversal::Reference runs (docs/stylize.md "Algorithm and schedule"). The fast
    //! schedule equals it bit for bit in every case (tests/stylize/registry_traversal_test.cpp).
    enum class Reference {
        PlainLoop,    //!< an independent plain loop over the per-pixel (per-tap) maths
        SharedMaths,  //!< the fast schedule calls the per-pixel function itself (nothing restated)
        SameKernel,   //!< the fast row kernel on one thread: not independent (listed as pending)
    };
    Reference reference = Reference::SameKernel;
    //! Input and output ports (names) the stage can compute in place (docs/stylize.md "In-place
    //! steps"): handed one image as both, it writes only the pixels that change, with the bytes of
    //! the run on separate images. Empty: never in place.
    std::string in_place_input = {}, in_place_output = {};
    //! Row windows (docs/stylize.md "Row groups"): when set, the Fast traversal run with a window
    //! (Exec::rows) computes exactly the output rows [y0, y1), reads its inputs only in the rows
    //! [y0 - halo, y1 + halo) (halo = row_halo(params); image borders resolved within them), writes
    //! outputs of its full-size input's size, and with an empty window only checks and allocates.
    //! Such steps in a row run band by band (CompiledPipeline::row_groups). Null: never windowed.
    std::function<int(const ParamValues&)> row_halo = {};
    //! Parameter values the variant takes from the scene being rendered (docs/stylize.md "Scene
    //! inputs"; stylize::apply_scene_inputs): set before the scene file's style values and --set,
    //! which override them. Null: none.
    SceneParamsFn scene_params = {};
    //! The step applies WC17 eq. 6's pigment turbulence in image space: without such a step in the
    //! pipeline the material applies it in object space (WC17 §3.2; raster::RenderSettings::turbulence).
    bool image_space_turbulence = false;
    //! The rules between parameters that ranges cannot state (smooth_high > smooth_low, ...):
    //! throws aq::Error naming the rule. Run when a pipeline compiles the step (resolve_step), so
    //! every single value may pass through a transient state while --set and a scene file apply
    //! theirs in turn. Null: none.
    std::function<void(const ParamValues&)> validate = {};
    //! The run with parameter values bound once, typed (declare sets it): what a compiled
    //! pipeline keeps per step (CompiledStep::step). Null: bound() keeps the values for `run`.
    std::function<StepFn(const ParamValues&)> bind = {};
    //! bind(params), or run with `params` kept.
    StepFn bound(const ParamValues& params) const;
    std::string key() const { return stage + "/" + variant; }
};

//! row_halo of a variant whose output pixel reads its inputs' pixel at the same place only.
inline int pointwise_rows(const ParamValues&) { return 0; }

//! Two consecutive steps run as one (a fused schedule; docs/stylize.md "Fused steps"): a producer
//! whose every output is read by the next step alone (the consumer) through the ports `links`
//! names, so the fused run can compute what the consumer reads without writing the producer's
//! images (glaze computing its colour-ramp rows from the lighting map instead of reading
//! color_ramp's four maps). The consumer's outputs are bit for bit the unfused run's
//! (tests/stylize/fusion_test.cpp). compile_pipeline finds the pairs; run_pipeline fuses them when
//! RunOptions::fuse is set (the producer's outputs then never exist).
struct Fusion {
    std::string producer, consumer;  //!< variant keys, "stage/variant"
    //! Every producer output port, each with the consumer input port that reads it.
    std::vector<std::pair<std::string, std::string>> links;
    std::string doc;
    //! producer: the producer's inputs (no outputs); consumer: its inputs, those of `links` null,
    //! and its outputs to fill.
    std::function<void(const StageIO& producer, const ParamValues& producer_params, StageIO& consumer,
                       const ParamValues& consumer_params, const Exec& ex)>
        run;
};

//! The framework's entry check of every variant (Registry::add puts it before run and the bound
//! step): as many inputs and outputs as declared, required inputs present and non-empty, every
//! input's channel count as its port declares, every output bound. Stages still check what only
//! they know (sizes, resolutions), once, at their own entry. Throws aq::Error naming `key`.
void check_io(const std::string& key, const std::vector<Port>& inputs, const std::vector<Port>& outputs,
              const StageIO& io);

class Registry {
public:
    //! Adds a variant, its run and bound steps behind check_io; throws aq::Error on a duplicate
    //! stage/variant, no run, a parameter declared twice or a bad in-place pair.
    void add(StageVariant v);
    //! Throws aq::Error naming the stage and listing what exists.
    const StageVariant& get(const std::string& stage, const std::string& variant) const;
    const StageVariant& default_variant(const std::string& stage) const;  //!< first registered
    bool has(const std::string& stage, const std::string& variant) const;
    std::vector<std::string> stages() const;                      //!< in registration order
    std::vector<const StageVariant*> variants(const std::string& stage) const;
    std::vector<const StageVariant*> all() const;

    //! Defaults overlaid with `overrides`; throws aq::Error for unknown names, non-finite or
    //! out-of-range values, non-integers for Int and non-0/1 for Bool. `where` prefixes messages.
    //! The value `text` gives parameter `name` of v: a number, true/false, or one of the
    //! parameter's named values (ParamDesc::names). Throws aq::Error prefixed with `where`
    //! (listing the names where the parameter has some); the range is checked by resolve_params.
    static double param_value(const StageVariant& v, const std::string& name, const std::string& text,
                              const std::string& where);
    static ParamValues resolve_params(const StageVariant& v, const std::map<std::string, double>& overrides,
                                      const std::string& where);

    //! Adds a fused pair; throws aq::Error when either variant is unknown, a link names a port
    //! they do not have (channel counts must agree), or some producer output has no link.
    void add_fusion(Fusion f);
    //! The fusion of producer -> consumer (variant keys), or null.
    const Fusion* fusion(const std::string& producer, const std::string& consumer) const;
    const std::vector<Fusion>& fusions() const { return fusions_; }

private:
    std::vector<StageVariant> variants_;
    std::vector<Fusion> fusions_;
};

//! The registry holding every built-in stage variant (built once, thread-safe).
const Registry& builtin_registry();

//! Stages registered while the program runs — the Python module's prototypes (docs/python.md
//! "Prototyping a stage in Python"): one stage, one variant each, named apart from every built-in
//! stage. A pipeline step naming a stage no built-in registry has is looked up here. Registering
//! a name again replaces it for later pipelines; compiled ones keep the variant they resolved (a
//! registry is never freed). Thread-safe. Throws aq::Error for a built-in name or a bad variant.
void register_runtime_stage(StageVariant v);
//! The runtime registry holding `stage`, or null.
const Registry* runtime_registry(const std::string& stage);

void register_builtin_stages(Registry& r);  // stylize/stages/register.cpp, in pipeline order

//! The registry of raster passes (LD06: ../shared/spec/ld06.md): steps that draw the scene
//! (StageIO::globals->scene) instead of reading images only. Same variant, port and parameter
//! machinery as the stages; pipeline files name them with "pass" instead of "stage".
const Registry& builtin_pass_registry();

void register_builtin_passes(Registry& r);  // stylize/passes/register.cpp

}  // namespace aq::stylize
