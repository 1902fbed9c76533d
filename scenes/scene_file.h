// scenes/scene_file.h — JSON scene files and the single entry point the CLI uses.
//
// A scene file names a glTF model (or a procedural scene), the camera, lights, the mapping of
// vertex attributes / noise fields / control textures / constants onto the control targets of the
// spec (§1), per-material overrides, the stylization style and the output settings. The schema,
// with an example, is in docs/scenes.md; every key is checked: an unknown key or a wrong type is an
// aq::Error naming the file and the key path.
#pragma once

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "scenes/gltf_loader.h"
#include "scenes/noise.h"
#include "scenes/scene.h"

namespace aq::scene {

//! Layout of the per-vertex control the rules write (docs/scenes.md "Control layouts").
enum class ControlLayout {
    WC18,  //!< four signed [-1, 1] targets (pigment, substrate, edge, abstraction), spec §1 table
    WC17,  //!< one RGBA [0, 1] control (R distortion, G granulation, B edge darkening + bleeding,
           //!< A turbulence + fading), mapped onto the WC18 targets by map_wc17_control()
};

//! One control-mapping rule: value = source * scale + bias, written into one channel.
struct ControlRule {
    enum class Source { Attribute, Noise, Texture, Constant };
    Source source = Source::Constant;
    // Destination: WC18 layout -> target 0..3 and channel 0..2 (texture rules: whole target,
    // channel = -1); WC17 layout -> target = -1 and channel 0..3 (R, G, B, A).
    int target = -1;
    int channel = 0;
    std::string attribute;  //!< "COLOR_0", "TEXCOORD_1", "_CUSTOM" (Attribute)
    int component = 0;      //!< 0..3 of the attribute (r/x .. a/w)
    NoiseField noise;       //!< Noise (object-space position)
    std::string file;       //!< Texture: resolved path
    float scale = 1.0f, bias = 0.0f;
    float value = 0.0f;                  //!< Constant
    std::vector<std::string> materials;  //!< restrict to materials (names or decimal indices); empty = all
};

//! The WC17 -> WC18 mapping (docs/scenes.md): R -> substrate.r, G -> pigment.g,
//! B -> edge.r and abstraction.b, A -> pigment.b = 1 - 2A (A < 0.5 turbulence/accumulate,
//! A > 0.5 fading/dilute; 0.5 is neutral). Inputs are clamped to [0, 1].
void map_wc17_control(const glm::vec4& wc17, std::array<glm::vec4, kNumControlTargets>& wc18);

//! Applies rules to every primitive of the scene (rules read object-space positions and vertex
//! attributes). Channels no rule writes keep their values; a written channel is the sum of its
//! rules, clamped to [-1, 1] (WC18) or [0, 1] (WC17, then mapped; unwritten WC17 channels are
//! neutral: 0, 0, 0, 0.5). Texture rules load the file, map texel t to the signed control
//! v = t*scale + bias (default 2, -1: 0.5 grey is neutral), store (v + 1) / 2 (the rasterizer
//! decodes a control texel as 2t - 1) and set Material::wc.control_texture. `where` prefixes
//! messages; warnings (attribute missing on a primitive) go to scene.warnings.
void apply_control_rules(Scene& scene, const std::vector<ControlRule>& rules, ControlLayout layout,
                         const std::string& where = "control",
                         const std::function<bool(const Primitive&)>& only = nullptr);

//! Control rules from JSON text (an array in the scene-file schema of docs/scenes.md), as the
//! pipeline presets' "default_control" holds them. Only noise and constant sources are accepted
//! (the rules apply to models of unknown attributes). `where` prefixes error messages.
std::vector<ControlRule> parse_control_rules(const std::string& json_array_text, const std::string& where,
                                             ControlLayout layout = ControlLayout::WC18);

//! A primitive carries painted control when any of its control targets has per-vertex values or
//! its material adds a constant control or a control texture.
bool has_painted_control(const Scene& scene, const Primitive& p);

//! The default art-direction (docs/look.md): applies `rules` (WC18 layout) to every primitive
//! without painted control (has_painted_control false). Returns the number of primitives changed.
std::size_t apply_default_control(Scene& scene, const std::vector<ControlRule>& rules,
                                  const std::string& where = "default control");

//! Hand-made strokes a scene file may list (raster/strokes.h has the pass's own, larger bounds).
inline constexpr std::size_t kMaxSceneStrokes = 100'000;
inline constexpr std::size_t kMaxSceneStrokeVertices = 1'000'000;

struct SceneDesc {
    Scene scene;
    Camera camera;                                     //!< the camera to render with
    std::string style = "wc18";                        //!< pipeline preset name or JSON path (may be empty)
    std::map<std::string, double> style_set;           //!< "stage.param" -> value overrides
    std::map<std::string, std::string> style_variant;  //!< "stage" -> variant
    int width = 0, height = 0;                         //!< 0 = not set by the file
    float fps = 24.0f;
    std::string paper;                                 //!< optional paper file, resolved path
    glm::vec3 substrate_color{1.0f};
    bool substrate_color_set = false;                  //!< the file named a substrate colour (it then replaces the style's)
    //! The camera was framed automatically (camera "auto", bare glTF). The framing used
    //! `auto_aspect` (the file's width/height, else 16:9); a caller rendering at another aspect
    //! should call frame_bounds(scene.world_bounds(), its_aspect, auto_view_dir, auto_yfov).
    bool camera_auto = false;
    glm::vec3 auto_view_dir{-0.35f, -0.3f, -1.0f};
    float auto_yfov = 0.6f;
    float auto_aspect = 16.0f / 9.0f;
    //! The scene file has a "control" key: its rules (even none) are the art-direction, and a
    //! style's default control is not applied (docs/look.md).
    bool control_rules = false;
    //! LD06 implicit-surface parameters from the scene file's "foliage" block (T, radius relative
    //! to the plant height unless "relative": false, cells_per_radius); they replace the style's
    //! values when the style abstracts foliage (docs/ld06.md). Unset: the style's.
    std::optional<float> foliage_threshold, foliage_radius;
    std::optional<bool> foliage_relative;
    std::optional<int> foliage_cells_per_radius;
    //! LD06 technique for the foliage: "auto", "surface" or "texture" (docs/ld06.md "Choosing the technique").
    std::optional<std::string> foliage_technique;
};

//! One value of a scene file's art direction that may be edited (SceneEdit): every number, bool
//! and array of 2 to 4 numbers under "control", "layers", "foliage", "lights", "ambient",
//! "substrate_color" and "materials" (names, sources and file paths are not values; hand-made
//! strokes are geometry). At most kMaxSceneKnobs, in file order.
struct SceneKnob {
    std::string pointer;  //!< RFC 6901, e.g. "/layers/1/color"
    std::string kind;     //!< "number", "integer", "bool", "color" (3 numbers named *color/dark/light/ambient in [0, 1]), "vector"
    std::string value;    //!< as JSON text
    std::string group;    //!< for a panel: the block or its element, named by its "name", "target" or "comment" ("layers[1] crown")
    std::string name;     //!< the keys inside the group ("color", "noise.amplitude")
};
inline constexpr std::size_t kMaxSceneKnobs = 512;
inline constexpr std::size_t kMaxSceneEdits = 512;

//! "POINTER=VALUE" (render --scene-set, the manifest's "scene_set") as a SceneEdit; throws
//! aq::Error when the pointer does not start with '/' or there is no '='. The value is checked
//! when the scene file is read.
SceneEdit parse_scene_edit(const std::string& text);
inline std::string to_string(const SceneEdit& e) { return e.pointer + "=" + e.value; }

//! The editable values of a scene file (reads and parses it; throws aq::Error as load_scene).
std::vector<SceneKnob> scene_knobs(const std::string& scene_file);

//! What names a procedural scene instead of a file: "procedural:NAME".
inline constexpr const char* kProceduralPrefix = "procedural:";

//! A scene file (.json), a bare .gltf/.glb (camera framing the bounds, a default light, neutral
//! control) or "procedural:NAME" (its own camera and lights). Throws aq::Error.
SceneDesc load_scene(const std::string& path_or_spec, const LoadOptions& options = {});

//! Perspective camera looking along view_dir (need not be normalised) at the bounds' centre, far
//! enough that the bounding sphere fits the smaller of the vertical and horizontal fields of view;
//! near/far hug the sphere. Up is +Y (-Z when view_dir is vertical). Invalid bounds: a camera at
//! (0, 0, 5) looking at the origin.
Camera frame_bounds(const Bounds& b, float aspect, glm::vec3 view_dir = {-0.35f, -0.3f, -1.0f}, float yfov = 0.6f);

//! The light used when a scene names none: white, intensity 1, from the upper left front.
Light default_light();

}  // namespace aq::scene
