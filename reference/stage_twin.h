// reference/stage_twin.h — runs the GLSL twin of a registered stage variant (docs/reference.md).
//
// Each variant `<stage>/<variant>` has one file reference/shaders/<stage>.<variant>.glsl written from
// ../shared/spec/watercolor.md and the papers, independently of stylize/. The file starts with
// directives, in comments, that declare its passes:
//
//   //@pass <name> out=<1..4> [size=[half:|half_if_<param>:]<input>] [in=<input>[:linear][:mirror],...]
//   //@output <port>=<pass>
//   //@include <file>          (replaced by reference/shaders/<file>: bodies shared by variants; nested, 4 levels)
//
// An <input> is a stage input port name, an earlier pass name, or `paper` (Globals::paper). A pass
// is compiled from the whole file with `#define PASS_<name>`; it sees each of its inputs as
// `uniform sampler2D s_<input>` ('.' -> '_'), `HAS_<input>` (0 when an optional input is absent),
// every stage parameter as `u_<param>` (float, int or bool, generated from the variant's ParamDesc
// list so a twin cannot miss or misspell one), the paper colour `u_substrate_color` and its output
// size `u_out_size`. size= defaults to the size of the pass's first input; half:<input> is
// ((w + 1) / 2, (h + 1) / 2); half_if_<param>:<input> is half when the Bool parameter is set;
// div_<param>:<input> is (ceil(w / k), ceil(h / k)) for the Int parameter k. Outputs without an
// @output line are bound to the last pass when the stage has one output.
#pragma once

#include <string>
#include <vector>

#include "core/image.h"
#include "reference/gl_runner.h"
#include "stylize/stage.h"

namespace aq::ref {

//! "<stage>.<variant>.glsl"
std::string twin_file(const stylize::StageVariant& v);
bool has_twin(const stylize::StageVariant& v);

//! A parsed twin, ready to run many times (programs are compiled on first run and cached).
class StageTwin {
public:
    explicit StageTwin(const stylize::StageVariant& v);  //!< throws aq::Error on a malformed file

    //! Runs on textures already on the GL side; `inputs` parallel to v.inputs (nullptr = absent
    //! optional input). `paper` may be null. Returns one texture per v.outputs entry.
    std::vector<Texture> run(const std::vector<const Texture*>& inputs, const stylize::ParamValues& params,
                             const glm::vec3& substrate_color, const Texture* paper) const;

    //! Convenience: uploads, runs, reads back.
    std::vector<ImageF> run(const std::vector<const ImageF*>& inputs, const stylize::ParamValues& params,
                            const stylize::Globals& globals) const;

    int num_passes() const { return int(passes_.size()); }

private:
    struct In {
        std::string name, ident;
        Filter filter = Filter::Nearest;
        Wrap wrap = Wrap::Clamp;
    };
    struct PassDecl {
        std::string name;
        int channels = 4;
        std::string size_of;  //!< input whose size the pass takes
        bool half = false;
        std::string half_param;  //!< half size when this Bool parameter is set
        std::string div_param;   //!< size ceil(w / k), k this Int parameter (size=div_<param>:<input>)
        std::vector<In> inputs;
    };
    const stylize::StageVariant* v_;
    std::string source_;
    std::vector<PassDecl> passes_;
    std::vector<std::string> output_pass_;  //!< per v.outputs
};

//! GLSL declarations of the variant's parameters as uniforms u_<name> (float / int / bool).
std::string param_uniform_decls(const std::vector<stylize::ParamDesc>& params);

}  // namespace aq::ref
