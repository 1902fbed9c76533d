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
#include "raster/foliage.h"
#include "stylize/paper.h"
#include "stylize/stage.h"

namespace aq::stylize {

//! The target holding the paper (prepare_paper at the image size, or the flat paper): added by
//! run_pipeline unless the caller put it there first (the render job prepares it before the
//! G-buffer of a one-shot render, so the paper file's decoding does not add to the peak memory).
inline constexpr const char* kPaperTarget = "paper";

struct PipelineStep {
    std::string stage, variant;                  //!< registry names; variant "" = the stage's default
    bool pass = false;                           //!< a raster pass (builtin_pass_registry; "pass" in files)
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
    //! LD06 §4.1: the raster passes draw the foliage as its implicit surface ("foliage" block;
    //! docs/ld06.md "Implicit surface"). Off unless the file has the block.
    raster::FoliageParams foliage;
    bool has_foliage = false;
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

//! "step.param" -> {step, param} (param empty when there is no dot): the one parser of the name
//! part of --set, --sweep and scene-file style values.
std::pair<std::string, std::string> split_step_param(const std::string& step_dot_param);

//! "step.param=value" where step is a step id or stage name (ambiguous names are an error);
//! values: numbers, true/false. Throws aq::Error on unknown step/param or out-of-range values.
void set_param(Pipeline& p, const std::string& assignment);
//! Sets one parameter by number (no text round trip), checked against its range; `source` names
//! where the value came from in the error ("scene file 'x.json' style.set", "automatic depth range").
void set_param_value(Pipeline& p, const std::string& step, const std::string& param, double value,
                     const std::string& source);
//! "step=variant". Parameters the new variant does not have are an error (named).
void set_variant(Pipeline& p, const std::string& assignment);
//! --bypass STEP: removes the step (id or stage name) and hands each of its outputs' readers, and
//! the pipeline's output, the step's input of the same port name instead (the step's input passes
//! through). A step with an output that has no same-named input (bleed writes `bleed`, edge_blur
//! `blurred`) cannot be bypassed: the error names the steps reading it, which can. Steps whose
//! outputs nobody reads any more stay (their targets are still written by --targets).
void bypass_step(Pipeline& p, const std::string& step);
//! Some step's variant applies the pigment turbulence in image space
//! (StageVariant::image_space_turbulence).
bool has_image_space_turbulence(const Pipeline& p);

struct RunOptions {
    Exec exec;
    std::function<void(int index, int count, const std::string& step)> progress;
    //! Frame loops: targets that the pipeline writes and that are already in `targets` are taken
    //! as the previous frame's outputs — removed before validation and their storage handed back
    //! to the stages (no re-allocation and page faults per frame). Off: such targets are an error.
    bool reuse_outputs = false;
    //! One-shot renders that write only the output: an intermediate is dropped from `targets` after
    //! the last step that reads it (CompiledPipeline::last_read), so its buffer goes back to the
    //! image pool (core/image.h) and the next output of that size reuses its pages instead of
    //! first-touching new ones. The output, the G-buffer and the paper are kept. Off: every
    //! intermediate stays in `targets` (--targets, tests).
    bool release_dead = false;
    //! With release_dead, for a one-shot render whose G-buffer is not kept (issue 13 item 6): the
    //! G-buffer targets are released too — those no step reads before the first step, the others
    //! after their last reader — so their memory serves the intermediates. The caller must not
    //! need the G-buffer afterwards. The paper stays (stages read it through Globals); the decoded
    //! paper file is dropped from prepare_paper's cache once the paper is prepared.
    bool release_inputs = false;
    //! The scene raster passes draw (pipelines with "pass" steps); its output size is the image
    //! size when the pipeline reads no G-buffer target.
    const raster::PassScene* scene = nullptr;
    //! Non-fatal problems reported by steps (may be null).
    std::vector<std::string>* warnings = nullptr;
    //! When set: resized to the step count and filled with each step's wall time in milliseconds
    //! (benchmarks' per-column splits, reports; a fused pair's time is its consumer's).
    std::vector<double>* step_ms = nullptr;
    //! Runs the fusable step pairs of CompiledPipeline::fused_with_next as one (stage.h Fusion):
    //! the same output bytes, but the producers' outputs are never written, so they are not in
    //! `targets` afterwards. For callers that keep only the output (the render job without
    //! --targets); off: every step runs alone.
    bool fuse = false;
    //! Runs the steps of CompiledPipeline::row_groups band by band (Fast traversal only; docs/stylize.md
    //! "Row groups"): the same output bytes and the same targets as step by step, with each band's
    //! intermediate rows read again while they are in the cache. Off by default: on our machines
    //! (arithmetic-bound stages, prefetched rows) it measured no faster than step by step
    //! (docs/performance.md "Where things stand"); `aquarelle render --row-groups` turns it on.
    bool row_groups = false;
    //! Rows per band of a row group (each step of the group advances by this many rows at a time).
    int band_rows = 16;
    //! Runs the steps of CompiledPipeline::in_place on their input's image (stage.h
    //! StageVariant::in_place_input): the same output bytes, but that input is not in `targets`
    //! afterwards. For the same callers as `fuse`.
    bool in_place = false;
    //! Runs steps first_step.. only: the outputs of the steps before it must be in `targets`, as a
    //! run of the same pipeline with every intermediate kept left them, and those steps' parameters
    //! unchanged since (the live view, app/serve.h: a parameter change re-runs from the first step
    //! that reads it). Only with fuse, in_place, row_groups and release_dead off.
    int first_step = 0;
};

//! One step of a compiled pipeline: the variant resolved, every parameter value checked and
//! complete, every port bound to a target name.
struct CompiledStep {
    const StageVariant* variant = nullptr;
    bool pass = false;  //!< a raster pass (needs RunOptions::scene)
    ParamValues params;
    //! The variant's run with `params` bound (StageVariant::bound): what the pipeline runs.
    StepFn step;
    std::vector<std::string> inputs;   //!< per variant input port
    std::vector<std::string> outputs;  //!< per variant output port
    std::string label;                 //!< "id (stage/variant)", for progress
    std::string where;                 //!< "FILE: steps[i] (stage/variant)", for errors
};
using ResolvedStep = CompiledStep;

//! A target the pipeline reads but no step writes: it must come from the G-buffer.
struct ExternalInput {
    std::string target;
    int channels = 0;       //!< what the first reader needs
    bool optional = false;  //!< every reader's port is optional
    std::string reader;     //!< "FILE: steps[i] (stage/variant)" of the first reader
    std::string port;       //!< the first reader's port name
};

//! Consecutive steps that run band by band (a fused schedule, Halide's compute_at with sliding
//! windows; docs/stylize.md "Row groups"): every step's variant declares a row halo
//! (StageVariant::row_halo), none is a raster pass or in a fused pair. The image is cut into
//! horizontal stripes run in parallel; within a stripe each step computes the next rows its
//! inputs allow, so a band's intermediate rows are read by the next steps while they are in the
//! cache; the rows around the stripe boundaries follow once every stripe is done. Every row of
//! every step is computed once, by the same row code as step by step: the same bytes.
struct RowGroup {
    std::size_t first = 0, last = 0;  //!< steps [first, last] of CompiledPipeline::steps
    //! Per step of the group: how many rows its computed rows stay behind those of the steps before
    //! it — the largest (depth of an in-group step whose output it reads + its own halo), 0 when it
    //! reads no output of the group (its inputs are complete before the group runs); a step that
    //! computes over its input in place stays behind every earlier reader of that input by the
    //! reader's depth + halo (it must not overwrite rows they will still read).
    std::vector<int> depth;
    int max_depth = 0;
};

//! A pipeline validated and resolved once (compile_pipeline); running it resolves nothing again.
struct CompiledPipeline {
    std::string name, source, output;
    glm::vec3 substrate_color{1.0f};
    PaperSpec paper;
    bool has_paper = false;
    std::vector<CompiledStep> steps;
    std::vector<ExternalInput> external;  //!< G-buffer targets read (and the output, if no step writes it)
    std::vector<std::string> produced;    //!< targets the steps write, in order
    //! Liveness: target -> index of the last step that reads it (intermediates are dead after it).
    std::map<std::string, std::size_t> last_read;
    //! Per step: the fusion with the next step when they can run as one — every output of this step
    //! is read by the next step alone, through the fusion's links, and none is the pipeline's
    //! output; a step is in one pair at most. Null otherwise. Used with RunOptions::fuse.
    std::vector<const Fusion*> fused_with_next;
    //! Per step: the index of the input port whose image the step may compute its in-place output
    //! over, or -1 — the variant declares the pair, the input is an intermediate (written by an
    //! earlier step, not the pipeline's output) that no other port of the step and no later step
    //! reads, and the step is in no fused pair. Used with RunOptions::in_place.
    std::vector<int> in_place;
    //! Row groups of two or more steps, in step order (RowGroup). Used with RunOptions::row_groups.
    std::vector<RowGroup> row_groups;
    bool has_passes = false;  //!< some step is a raster pass
    raster::FoliageParams foliage;  //!< see Pipeline::foliage
    bool has_foliage = false;
};

//! Checks everything that can be checked without running — stage/variant/param names and ranges,
//! port names, every input produced by an earlier step or external, no step writing its own
//! input, the paper target or a target written before, and that `output` is produced or external
//! — and returns the resolved plan. With a G-buffer, also check_gbuffer. Throws aq::Error naming
//! the file, the step and the key.
CompiledPipeline compile_pipeline(const Pipeline& p, const Targets* gbuffer = nullptr);

//! The G-buffer side of validation, cheap enough for every frame: every non-optional external
//! input present with its channel count, all external inputs of equal size, no step output
//! overwriting a G-buffer target. Throws aq::Error.
void check_gbuffer(const CompiledPipeline& c, const Targets& gbuffer);

//! Runs a compiled pipeline on `targets` (the G-buffer): check_gbuffer, then each step in order,
//! adding its outputs to `targets`. The paper texture is added as target "paper" (flat paper when
//! the pipeline has none). Throws aq::Error naming the step on any failure.
void run_pipeline(const CompiledPipeline& c, Targets& targets, const RunOptions& opt = {});

//! compile_pipeline(p, &targets) then run_pipeline: for callers that run a pipeline once.
void run_pipeline(const Pipeline& p, Targets& targets, const RunOptions& opt = {});

//! compile_pipeline without keeping the plan.
void validate_pipeline(const Pipeline& p, const Targets* gbuffer = nullptr);

//! One step resolved (as compile_pipeline does for each).
ResolvedStep resolve_step(const Pipeline& p, std::size_t index);

}  // namespace aq::stylize
