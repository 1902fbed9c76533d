// scenes/scene.h — the in-memory scene every loader produces and the rasterizer consumes.
//
// Loaders (glTF, scene files, procedural generators) resolve everything that does not depend on
// the view: triangle lists (strips and fans expanded), normals and tangents computed where
// missing, vertex colours widened to RGBA float, and the per-vertex control values already mapped
// onto the four WC18/MNPR control targets (spec §1). The rasterizer only transforms and shades.
#pragma once

#include "core/targets.h"

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/image.h"
#include "core/io.h"

namespace aq::scene {

enum class Wrap { Repeat, ClampToEdge, MirroredRepeat };
enum class Filter { Nearest, Linear };
//! How a minified texture uses its mip levels (GL's *_MIPMAP_* minification filters).
enum class MipFilter { None, Nearest, Linear };

//! A glTF sampler. `min` filters within a mip level, `mip` between levels (glTF minFilter 9984-9987
//! set both; 9728/9729 give MipFilter::None). A sampler a file leaves undefined is trilinear
//! (LINEAR_MIPMAP_LINEAR): docs/raster.md "Texture filtering".
struct Sampler {
    Wrap wrap_s = Wrap::Repeat, wrap_t = Wrap::Repeat;
    Filter mag = Filter::Linear, min = Filter::Linear;
    MipFilter mip = MipFilter::Linear;
};

//! Level 0 of an 8-bit texture as codes, with the float each code stands for: texel (x, y) as the
//! rasterizer reads it is {lut[0][c0], lut[1][c1], lut[2][c2], lut[3][c3]}, c = codes[4 (y w + x) ..]
//! (a quarter of RGBA float's bytes: less memory, fewer cache misses when sampled).
struct TextureCodes {
    int width = 0, height = 0;
    UninitializedVector<std::uint8_t> codes;         //!< 4 per texel; empty: not 8-bit
    std::array<std::array<float, 256>, 4> lut{};     //!< per lane, the value of each code
    bool empty() const { return codes.empty(); }
    //! Texel (x, y): each lane's code through its table.
    glm::vec4 texel(int x, int y) const {
        const std::uint8_t* c = codes.data() + 4 * (std::size_t(y) * std::size_t(width) + std::size_t(x));
        return {lut[0][c[0]], lut[1][c[1]], lut[2][c[2]], lut[3][c[3]]};
    }
};

//! Step 1 of a compact texture, on the image as decoded from its file (before any per-value
//! mapping): the codes round(v * 255) of an image of 8-bit values (each code always from the same
//! float), else empty (16-bit or float files, values outside [0, 1], NaN).
TextureCodes texture_codes(const ImageF& decoded);
//! Step 2, on the final image (after a per-value mapping such as the sRGB decode, the same shape):
//! fills the look-up tables with the final values and keeps the codes only when every value of
//! the image equals its code's table entry, bit for bit (else c is emptied).
void texture_codes_finish(TextureCodes& c, const ImageF& final_image);

//! The per-value mapping a loader applies to a texture's decoded values, lane by lane (R, G, B, A):
//! the same float function whether the texture is kept as codes (applied to each code's value)
//! or as floats (applied to each value).
struct TexelMap {
    enum class Kind {
        Identity,
        Srgb,     //!< R, G, B from sRGB-encoded to linear (glTF base colour, §3.9.2); alpha as stored
        Control,  //!< every lane v -> (v scale + bias + 1) / 2 (scene-file control textures)
    };
    Kind kind = Kind::Identity;
    float scale = 1.0f, bias = 0.0f;  //!< Control only
    float operator()(float v, int lane) const;
};

struct Texture {
    std::string name;  //!< URI or image name, for messages
    //! Level 0 as RGBA float, for a texture whose values are not 8-bit (16-bit, float and HDR
    //! files); empty when `codes` hold level 0. Values as stored, mapped by the loader's TexelMap
    //! (an sRGB texture, srgb = true, has its RGB decoded to linear so filtering happens in linear
    //! as GL's sRGB textures do: docs/look.md "Colour management").
    ImageF image;
    bool srgb = false;  //!< the file declares the values sRGB-encoded (glTF base colour)
    //! Level 0 as 8-bit codes, where the file held 8-bit values (then `image` is empty).
    TextureCodes codes;
    //! Mip levels 1, 2, ... (level 0 is `image` or `codes`): level k is max(1, w >> k) x
    //! max(1, h >> k), down to 1 x 1, each the area average of the level above
    //! (texture_mip_level), in level 0's values (linear light for sRGB textures; colour weighted by
    //! alpha in a colour texture with transparent texels). Built once by finish_texture; empty:
    //! only level 0 (then every minified sample reads level 0). With level1_computed, mips[0] is
    //! empty: level 1 is computed texel by texel where it is sampled (level1_texel).
    std::vector<ImageF> mips;
    //! Level 1 is not stored (a large opaque RGBA texture, kComputedLevel1Bytes).
    bool level1_computed = false;
    //! Texel (x, y) of level 1 from level 0: the value texture_mip_level stores there, bit for bit.
    glm::vec4 level1_texel(int x, int y) const;
    //! Every mip level, level 1 built where it is computed (a copy), for code that reads them all
    //! (the GL twins).
    std::vector<ImageF> all_mips() const;

    bool empty() const { return image.empty() && codes.empty(); }
    int width() const { return codes.empty() ? image.width() : codes.width; }
    int height() const { return codes.empty() ? image.height() : codes.height; }
    //! Level 0's texel (x, y) as the rasterizer reads it (RGBA; a float image of fewer channels:
    //! one channel as grey, missing G/B as 0, missing alpha as 1).
    glm::vec4 texel0(int x, int y) const;
    //! Level 0 as an RGBA float image (a copy).
    ImageF level0() const;
};

//! A texture's level 1 is not stored but computed where sampled (Texture::level1_texel: the 4-9
//! level-0 texels of its box, the same sums) when storing it would take at least this many bytes
//! — a 1024 x 1024 RGBA float level, level 0 of 2048 x 2048 or more — and the texture is opaque
//! RGBA. At 1280 x 720 a 2K or 4K map is sampled at level 1 only in a few pixels (slanted
//! surfaces, anisotropic probes), while storing it touched 16-64 MB of fresh memory per map
//! (docs/performance.md "One-shot renders").
inline constexpr std::size_t kComputedLevel1Bytes = std::size_t(16) << 20;

//! The next mip level of `level`: max(1, w / 2) x max(1, h / 2) texels, each the area average of
//! the texels its footprint covers (2 taps per axis for an even size; for an odd size the 3 taps
//! of the exact box, weights (n' - i, n', i + 1) / n with n' = n / 2 — the NPOT mipmapping of
//! NVIDIA's "Non-Power-of-Two Mipmap Creation" note). Separable, rows then columns, float sums
//! in tap order: the same bits on every machine and thread count.
ImageF texture_mip_level(const ImageF& level);
//! The same level from 8-bit codes (RGBA): the values of codes.lut, the same bits as from the
//! equal float image.
ImageF texture_mip_level(const TextureCodes& level);
//! The loaders' last step for a texture whose level 0 (`image` or `codes`) is final: every mip
//! level down to 1 x 1 (level 1 of a large opaque texture computed where sampled instead:
//! kComputedLevel1Bytes). The levels add at most a third of RGBA float level 0's bytes.
void finish_texture(Texture& t);

struct TextureRef {
    int texture = -1;  //!< index into Scene::textures, -1 = none
    int texcoord = 0;  //!< which TEXCOORD_n (only 0 is loaded; others fall back to 0 with a warning)
    Sampler sampler;
    float scale = 1.0f;  //!< normalTexture.scale
};

enum class AlphaMode { Opaque, Mask, Blend };

//! Number of control targets in the WC18/MNPR layout (spec §1 table).
inline constexpr int kNumControlTargets = control::kNumTargets;
//! Indices into core/targets.h control::kTargets.
enum ControlTarget { kCtrlPigment = 0, kCtrlSubstrate = 1, kCtrlEdge = 2, kCtrlAbstraction = 3 };

//! MNPR's reflectance defaults (the authors' Maya material; WC17 Fig. 7 uses dA = 1): kept for
//! reproducing the papers (procedural:swatches, mnpr_watercolor_material()).
inline constexpr float kMnprDilute = 0.8f;
inline constexpr float kMnprCangiante = 0.2f;
inline constexpr float kMnprDiluteArea = 1.0f;
//! Defaults for materials that name none (bare glTF models; docs/look.md "Material defaults"):
//! MNPR's d = 0.8 pulls every lit face 80 % of the way to the paper and hides the model's colours.
//! d = 0.35 with dA = 0.6 dilutes only faces turned towards the key light (N.L > 0.4), at most
//! 35 %; c = 0.1 keeps a visible warm/cool shift without washing the hue out.
inline constexpr float kDefaultDilute = 0.35f;
inline constexpr float kDefaultCangiante = 0.1f;
inline constexpr float kDefaultDiluteArea = 0.6f;

//! Per-material watercolor parameters: the second of WC18 §5's three levels of control.
struct WatercolorMaterial {
    // Reflectance model, WC17 eq. 3-5 (bare-model defaults; MNPR's are kMnpr*).
    float dilute = kDefaultDilute;            //!< d, [0, 1]
    float cangiante = kDefaultCangiante;      //!< c, [0, 1]
    float diffuse_factor = 0.2f;              //!< k in DF = lerp(1, sat(N.L), k), [0, 1] (MNPR)
    float dilute_area = kDefaultDiluteArea;   //!< dA, [0.01, 1]
    float shade_wrap = 0.0f;    //!< wraps the diffuse term, [0, 1]
    glm::vec3 shade_color{0.0f};//!< colour of the shaded side mixed by (1 - DF), MNPR default black (off)
    float specular = 0.0f;      //!< Blinn-Phong specular intensity, [0, 1]
    float specular_power = 32.0f;
    //! Constant control values added to the per-vertex ones (per target, RGB used).
    std::array<glm::vec4, kNumControlTargets> control{};
    //! Optional control textures sampled with TEXCOORD_0 (third source of control, spec §1).
    std::array<TextureRef, kNumControlTargets> control_texture{};
};

//! A WatercolorMaterial with MNPR's reflectance defaults (d 0.8, c 0.2, dA 1).
inline WatercolorMaterial mnpr_watercolor_material() {
    WatercolorMaterial w;
    w.dilute = kMnprDilute;
    w.cangiante = kMnprCangiante;
    w.dilute_area = kMnprDiluteArea;
    return w;
}

struct Material {
    std::string name;
    glm::vec4 base_color{1.0f};
    TextureRef base_color_texture;
    TextureRef normal_texture;
    AlphaMode alpha_mode = AlphaMode::Opaque;
    float alpha_cutoff = 0.5f;
    bool double_sided = false;
    //! glTF 2.0 colour semantics: base_color and COLOR_0 are linear and the base colour texture
    //! holds linear values (decoded by the loader); the rasterizer multiplies them in linear and
    //! encodes the product into the working space. false (procedural scenes, the papers' swatch
    //! colours): base_color and COLOR_0 are display-referred sRGB values, used as given.
    bool linear_color = false;
    WatercolorMaterial wc;
    //! LD06 §4.3 intensity texture (scene files: materials.NAME.intensity_texture): up to three
    //! hand-made detail maps in R, G, B, sampled with TEXCOORD_0 and rendered by the raster pass
    //! "intensity_texture" into three layer maps; values as stored (no colour decoding).
    TextureRef intensity_texture;
};

//! One draw: an indexed triangle list with a material.
struct Primitive {
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;   //!< always filled (computed when the file has none)
    std::vector<glm::vec4> tangents;  //!< filled when the material has a normal map, else empty
    std::vector<glm::vec2> uv0;       //!< empty when absent
    std::vector<glm::vec4> colors;    //!< COLOR_0 as RGBA float, empty when absent
    //! Per-vertex control values mapped onto the WC18 layout; an empty vector means zero.
    std::array<std::vector<glm::vec4>, kNumControlTargets> control;
    std::vector<std::uint32_t> indices;  //!< triangle list, 3 per triangle, all < positions.size()
    int material = 0;                    //!< index into Scene::materials (a default one exists)
    //! Further vertex attributes kept for the scene file's control mapping (COLOR_1..n,
    //! TEXCOORD_1..n, custom "_NAME"), widened to vec4 (missing components 0; colour alpha 1).
    //! The rasterizer does not read them.
    std::map<std::string, std::vector<glm::vec4>> attributes;
};

struct Mesh {
    std::string name;
    std::vector<Primitive> primitives;
};

//! A mesh placed in the world. object_id is unique per instance, starting at 1 (0 = background).
struct Instance {
    int mesh = 0;
    glm::mat4 world{1.0f};
    std::uint32_t object_id = 1;
    std::string name;
};

struct Camera {
    std::string name;
    glm::mat4 view{1.0f};   //!< world -> eye (right-handed, looking down -Z)
    bool orthographic = false;
    float yfov = 0.8f;      //!< radians, perspective
    float xmag = 1.0f, ymag = 1.0f;  //!< orthographic half extents
    float znear = 0.1f;
    float zfar = 100.0f;    //!< finite far plane (glTF infinite projections get a computed one)
    std::optional<float> aspect;     //!< glTF aspectRatio; when absent the image's is used
};

//! Directional light; direction points from the surface towards the light, world space.
struct Light {
    glm::vec3 direction{0.0f, 0.0f, 1.0f};
    glm::vec3 color{1.0f};
    float intensity = 1.0f;
};

struct Bounds {
    glm::vec3 min{0.0f}, max{0.0f};
    bool valid = false;
};

//! LD06 foliage chosen by name in a scene file ("foliage" key, docs/scenes.md): a primitive is
//! foliage when its instance (node), mesh or material name is listed. Unset: is_foliage's rule.
struct FoliageSelection {
    bool set = false;
    std::vector<std::string> nodes, meshes, materials;  //!< each sorted and unique (binary search)
    //! Adds a name keeping the list sorted and unique.
    static void add(std::vector<std::string>& list, const std::string& name);
};

//! LD06 §4.4 hand-made line stroke (scene files: "strokes"): a 3D polyline in world space, the
//! normals of the surface it belongs to (optional: n·v fade) and whether it is a hatching stroke
//! (faded by n·l). Drawn by the raster pass "strokes" (raster/strokes.h), in file order.
struct Stroke {
    std::vector<glm::vec3> points;   //!< world space, >= 2
    std::vector<glm::vec3> normals;  //!< per point, or empty
    bool light_dependent = false;    //!< hatching
};

//! LD06 §3.1 watercolor layer given in a scene file ("layers", docs/scenes.md): the primitives whose
//! instance (node), mesh or material name is listed form one layer, painted with `color` ramping to
//! `dark` (display values; unset: from the first member's material, scenes/layers.h).
struct LayerSpec {
    std::string name;
    std::vector<std::string> nodes, meshes, materials;
    std::optional<glm::vec3> color, dark;
    std::optional<float> alpha;
};

//! Bytes one render may decode into a scene (counted as RGBA float, 16 B/texel, from each image's
//! header before it is decoded), whatever names the image: the model's textures, the scene file's
//! intensity and control textures (docs/limits.md "Sizes"). 1 GiB = 64 Mpx (16 textures of 2048x2048).
inline constexpr std::size_t kMaxDecodedBytesPerRender = std::size_t(1) << 30;

//! A decode budget of `bytes` for one render's scene.
DecodeBudget render_decode_budget(std::size_t bytes = kMaxDecodedBytesPerRender);

struct Scene {
    std::vector<Mesh> meshes;
    std::vector<Instance> instances;
    std::vector<Material> materials;  //!< materials[0] may be the default material
    std::vector<Texture> textures;
    std::vector<Camera> cameras;
    std::vector<Light> lights;
    glm::vec3 ambient{0.0f};
    std::vector<std::string> warnings;  //!< non-fatal problems met while loading
    std::string source;                 //!< file it came from, for messages
    FoliageSelection foliage;           //!< LD06 foliage chosen by the scene file (see is_foliage)
    std::vector<Stroke> strokes;        //!< LD06 hand-made strokes (scene files)
    std::vector<LayerSpec> layers;      //!< LD06 layer groups (scene files); empty: one layer per material
    //! What is left of the render's decode budget: every image decoded into this scene draws from it.
    DecodeBudget decode_budget = render_decode_budget();

    Bounds world_bounds() const;  //!< over finite positions of all instances
    std::size_t triangle_count() const;
};

//! LD06 foliage (../shared/spec/ld06.md §5): the scene's FoliageSelection when set; otherwise
//! alpha-masked materials, and primitives whose material, mesh or instance name contains
//! "foliage", "leaf" or "leaves" (case-insensitive). docs/ld06.md "Foliage".
bool is_foliage(const Scene& sc, const Instance& inst, const Primitive& prim);

}  // namespace aq::scene
