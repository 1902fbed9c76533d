// stylize/pipeline.h — pipelines as data: an ordered list of stage variants reading and writing
// named targets (MNPR stage list / Filament frame graph), loaded from JSON presets
// (stylize/presets/*.json, or any user file) and validated completely before any stage runs.
// Schema and example: docs/stylize.md "Pipeline files".
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/exec.h"
#include "core/targets.h"
#include "stylize/paper.h"
#include "stylize/stage.h"

namespace aq::stylize {

struct PipelineStep {
    std::string stage, variant;                  //!< registry names; variant "" = the stage's default
    std::map<std::string, double> params;        //!< overrides of the variant's defaults
    std::map<std::string, std::string> in, out;  //!< port -> target; unbound ports use the defaults
    std::string id;                              //!< name used by set_param/set_variant (default: stage)
};

struct Pipeline {
    std::string name, doc, source;  //!< source: the file it came from (used in error messages)
    glm::vec3 substrate_color{1.0f};
    PaperSpec paper;
    bool has_paper = false;
    std::vector<PipelineStep> steps;
    std::string output = "color.final";  //!< target holding the final image
    //! Default art-direction (docs/look.md): a JSON array of control rules in the scene-file
    //! schema (docs/scenes.md "Control mapping", wc18 layout; noise and constant sources only),
    //! applied by the CLI to primitives without painted control. Empty = none. Kept as text:
    //! the rules are parsed and checked by aq::scene::parse_control_rules.
    std::string default_control;
};

//! A preset name ("wc18", looked up in $AQ_PRESET_DIR, else the compiled-in preset folder) or a
//! path to a .json file. Throws aq::Error naming the file and the key path ("wc18.json:
//! steps[3].params.width: ...") for malformed JSON, unknown stages/variants/params/ports and
//! out-of-range values.
Pipeline load_pipeline(const std::string& preset_name_or_json_path);

//! Pipeline from JSON text; `source` names it in messages. Same checks as load_pipeline.
Pipeline parse_pipeline(const std::string& json_text, const std::string& source,
                        const std::string& base_dir = "");

//! Preset names (file stems) in the preset folder, sorted.
std::vector<std::string> preset_names();
//! The preset folder in use ($AQ_PRESET_DIR or the compiled-in one).
std::string preset_dir();

//! "step.param=value" where step is a step id or stage name (ambiguous names are an error);
//! values: numbers, true/false. Throws aq::Error on unknown step/param or out-of-range values.
void set_param(Pipeline& p, const std::string& assignment);
//! Sets one parameter by number (no text round trip), checked against its range; `source` names
//! where the value came from in the error ("scene file 'x.json' style.set", "automatic depth range").
void set_param_value(Pipeline& p, const std::string& step, const std::string& param, double value,
                     const std::string& source);
//! "step=variant". Parameters the new variant does not have are an error (named).
void set_variant(Pipeline& p, const std::string& assignment);

struct RunOptions {
    Exec exec;
    std::function<void(int index, int count, const std::string& step)> progress;
    //! Frame loops: targets that the pipeline writes and that are already in `targets` are taken
    //! as the previous frame's outputs — removed before validation and their storage handed back
    //! to the stages (no re-allocation and page faults per frame). Off: such targets are an error.
    bool reuse_outputs = false;
};

//! Validates (validate_pipeline with the given targets as G-buffer), then runs each step in order,
//! adding its outputs to `targets`. The paper texture is added as target "paper" (flat paper when
//! the pipeline has none). Throws aq::Error naming the step on any failure.
void run_pipeline(const Pipeline& p, Targets& targets, const RunOptions& opt = {});

//! Checks everything that can be checked without running: stage/variant/param names and ranges,
//! port names, every input produced by an earlier step or present in the G-buffer (when given),
//! channel counts, no step writing its own input, a G-buffer target or a target written before,
//! equal sizes of the G-buffer inputs, and that `output` is produced. Throws aq::Error.
void validate_pipeline(const Pipeline& p, const Targets* gbuffer = nullptr);

//! Resolved view of a step: the variant, full parameter values and port -> target bindings.
struct ResolvedStep {
    const StageVariant* variant = nullptr;
    ParamValues params;
    std::vector<std::string> inputs;   //!< per variant input port ("" = optional and unbound)
    std::vector<std::string> outputs;  //!< per variant output port
};
ResolvedStep resolve_step(const Pipeline& p, std::size_t index);

}  // namespace aq::stylize
