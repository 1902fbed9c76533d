// reference/gl_runner.h — float textures, float framebuffers and a fullscreen-triangle pass runner
// for the GPU-equivalent reference (docs/reference.md).
//
// Conventions shared with the C++ stages:
// - Image row y is texture row y (no flip): a fragment at gl_FragCoord = (x + 0.5, y + 0.5) writes
//   pixel (x, y) of the ImageF read back, and texelFetch(s, ivec2(x, y), 0) reads pixel (x, y).
// - Exact taps use texelFetch with the border rule resolved in GLSL (reference/shaders/common.glsl),
//   because texelFetch ignores sampler wrap modes and GL_MIRRORED_REPEAT repeats the edge texel
//   whereas aq::Border::Mirror does not.
// - Bilinear taps use texture() on a GL_LINEAR sampler with GL_CLAMP_TO_EDGE (or mirrored repeat).
// - Everything is 32-bit float end to end: R32F/RG32F/RGB32F/RGBA32F textures, RGBA32F (or R32F,
//   RG32F) colour attachments, glReadPixels(GL_FLOAT).
#pragma once

#include <map>
#include <string>
#include <variant>
#include <vector>

#include <glm/glm.hpp>

#include "core/image.h"

namespace aq::scene {
struct Sampler;
}

namespace aq::ref {

//! A GL sampler object for a scene sampler: its wrap modes, magnification filter and
//! minification filter within and between mip levels (raster/material.h sample_texture). The
//! caller deletes it.
unsigned scene_sampler(const scene::Sampler& s);
//! A fragment shader's source with texture_filter.glsl (aq_texture: the CPU's anisotropic mip
//! filtering) in place of its `#include_texture_filter` line.
std::string with_texture_filter(std::string src);

enum class Filter { Nearest, Linear };
enum class Wrap { Clamp, Mirror };  //!< GL_CLAMP_TO_EDGE, GL_MIRRORED_REPEAT

//! A float texture on the GL side (move-only RAII). Channels 1..4.
class Texture {
public:
    Texture() = default;
    Texture(int w, int h, int channels);  //!< uninitialised storage; 3 channels stored as RGBA32F
    static Texture upload(const ImageF& img);
    //! Level 0 and the given mip levels 1, 2, ... (scene::Texture::mips: the CPU's own levels, so
    //! both sides filter the same texels; GL_TEXTURE_MAX_LEVEL = mips.size()).
    static Texture upload(const ImageF& level0, const std::vector<ImageF>& mips);
    ~Texture();
    Texture(Texture&& o) noexcept { *this = std::move(o); }
    Texture& operator=(Texture&& o) noexcept;
    Texture(const Texture&) = delete;
    Texture& operator=(const Texture&) = delete;

    unsigned id() const { return id_; }
    int width() const { return w_; }
    int height() const { return h_; }
    int channels() const { return c_; }
    bool valid() const { return id_ != 0; }

private:
    unsigned id_ = 0;
    int w_ = 0, h_ = 0, c_ = 0;
};

//! Reads a texture back as an ImageF with the texture's channel count (glReadPixels, GL_FLOAT).
ImageF read_texture(const Texture& t);

struct Input {
    const Texture* texture = nullptr;
    Filter filter = Filter::Nearest;
    Wrap wrap = Wrap::Clamp;
};

using UniformValue = std::variant<float, int, bool, glm::vec2, glm::vec3, glm::vec4, glm::ivec2, glm::mat4>;

//! One fullscreen pass: a complete fragment shader (with #version), its sampler inputs by uniform
//! name, its uniforms by name, and the output size and channel count.
struct Pass {
    std::string name;      //!< for messages
    std::string fragment;  //!< GLSL 4.50 core source writing `out vec4 o_color` (location 0)
    std::map<std::string, Input> inputs;
    std::map<std::string, UniformValue> uniforms;
    int width = 0, height = 0, channels = 4;
};

//! Runs the pass into a new float texture. Programs are compiled once per source and cached, so a
//! repeated pass pays the JIT cost only once. Unknown uniform/sampler names (optimised away by the
//! compiler) are ignored. Throws aq::Error with the compile/link log on shader errors.
Texture run_pass_texture(const Pass& pass);
//! run_pass_texture + read_texture.
ImageF run_pass(const Pass& pass);

//! Vertex attribute buffers of one draw (RAII): attrib(location, data, components) uploads a float
//! array and points the attribute at it; the buffers are deleted with the object. `ids` also
//! takes other buffers of the draw (an element buffer) to delete them together.
struct VertexBuffers {
    std::vector<unsigned> ids;
    VertexBuffers() = default;
    VertexBuffers(const VertexBuffers&) = delete;
    VertexBuffers& operator=(const VertexBuffers&) = delete;
    ~VertexBuffers();
    void attrib_floats(unsigned location, const void* data, std::size_t bytes, int components);
    template <class T>
    void attrib(unsigned location, const std::vector<T>& data, int components) {
        attrib_floats(location, data.data(), data.size() * sizeof(T), components);
    }
};

//! Compiles (cached) a program from a vertex and a fragment source; returns the GL name.
unsigned program(const std::string& vertex, const std::string& fragment, const std::string& what);
//! Sets a uniform on the currently bound program, if it is active.
void set_uniform(unsigned prog, const std::string& name, const UniformValue& v);

//! Reads a text file under reference/shaders (the path compiled in as AQ_REFERENCE_SHADER_DIR, or
//! $AQ_REFERENCE_SHADER_DIR). Throws aq::Error naming the path when missing.
std::string load_shader_file(const std::string& name);
std::string shader_dir();
bool shader_file_exists(const std::string& name);

//! Glues "#version 450 core", `defines` (one "#define ..." per entry), common.glsl and `body`.
//! With the environment variable AQ_REFERENCE_EXACT_BILINEAR=1 it also defines AQ_EXACT_BILINEAR,
//! which makes the twins' bilinear taps exact-weight texelFetch sums instead of texture() (a
//! diagnostic for GPUs, whose texture units quantise the weights; common.glsl).
std::string assemble_fragment(const std::string& body, const std::vector<std::string>& defines = {});

//! glFinish: waits until every queued command has executed (for timing).
void finish();

}  // namespace aq::ref
