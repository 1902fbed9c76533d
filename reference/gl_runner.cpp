// reference/gl_runner.cpp — textures, FBOs, program cache and the fullscreen pass.
#include "reference/gl_runner.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unordered_map>

#include <glm/gtc/type_ptr.hpp>

#include "reference/gl_api.h"
#include "reference/gl_context.h"
#include "scenes/scene.h"

namespace aq::ref {

namespace {

GLenum internal_format(int c) {
    switch (c) {
        case 1: return GL_R32F;
        case 2: return GL_RG32F;
        case 3: return GL_RGB32F;
        default: return GL_RGBA32F;
    }
}
GLenum pixel_format(int c) {
    switch (c) {
        case 1: return GL_RED;
        case 2: return GL_RG;
        case 3: return GL_RGB;
        default: return GL_RGBA;
    }
}

const char* kFullscreenVertex = R"(#version 450 core
// One triangle covering the viewport: (-1,-1), (3,-1), (-1,3).
void main() {
    vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
)";

std::string shader_log(GLuint s, bool is_program) {
    GLint n = 0;
    if (is_program) gl::GetProgramiv(s, GL_INFO_LOG_LENGTH, &n);
    else gl::GetShaderiv(s, GL_INFO_LOG_LENGTH, &n);
    std::string log(std::max(n, 1), '\0');
    if (is_program) gl::GetProgramInfoLog(s, n, nullptr, log.data());
    else gl::GetShaderInfoLog(s, n, nullptr, log.data());
    return log;
}

std::string numbered(const std::string& src) {
    std::istringstream in(src);
    std::ostringstream out;
    std::string line;
    for (int i = 1; std::getline(in, line); ++i) out << i << ": " << line << "\n";
    return out.str();
}

GLuint compile(GLenum type, const std::string& src, const std::string& what) {
    GLuint s = gl::CreateShader(type);
    const char* p = src.c_str();
    gl::ShaderSource(s, 1, &p, nullptr);
    gl::CompileShader(s);
    GLint ok = 0;
    gl::GetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        std::string log = shader_log(s, false);
        gl::DeleteShader(s);
        throw Error("GLSL compile error in " + what + ":\n" + log + "\nsource:\n" + numbered(src));
    }
    return s;
}

GlContext& context() {
    std::string why;
    GlContext* c = GlContext::shared(&why);
    if (!c) throw Error("no OpenGL context: " + why);
    return *c;
}

struct Fbo {
    GLuint fbo = 0, vao = 0;
};
Fbo& fbo_state() {
    static Fbo f;
    if (!f.fbo) {
        gl::GenFramebuffers(1, &f.fbo);
        gl::GenVertexArrays(1, &f.vao);
    }
    return f;
}

}  // namespace

Texture::Texture(int w, int h, int channels) : w_(w), h_(h), c_(channels) {
    context();
    check_image_size(w, h, "GL texture");
    gl::GenTextures(1, &id_);
    gl::BindTexture(GL_TEXTURE_2D, id_);
    // 3-channel render targets are stored as RGBA32F: RGB32F is not required to be colour-renderable.
    gl::TexImage2D(GL_TEXTURE_2D, 0, internal_format(c_ == 3 ? 4 : c_), w, h, 0, pixel_format(c_ == 3 ? 4 : c_),
                   GL_FLOAT, nullptr);
    gl::TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
    check_gl("allocating a float texture");
}

Texture Texture::upload(const ImageF& img) {
    context();
    Texture t;
    t.w_ = img.width();
    t.h_ = img.height();
    t.c_ = img.channels();
    gl::GenTextures(1, &t.id_);
    gl::BindTexture(GL_TEXTURE_2D, t.id_);
    gl::TexImage2D(GL_TEXTURE_2D, 0, internal_format(t.c_), t.w_, t.h_, 0, pixel_format(t.c_), GL_FLOAT,
                   img.data());
    gl::TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
    check_gl("uploading a float texture");
    return t;
}

Texture Texture::upload(const ImageF& level0, const std::vector<ImageF>& mips) {
    Texture t = upload(level0);
    for (std::size_t k = 0; k < mips.size(); ++k) {
        const ImageF& m = mips[k];
        gl::TexImage2D(GL_TEXTURE_2D, GLint(k + 1), internal_format(t.c_), m.width(), m.height(), 0,
                       pixel_format(t.c_), GL_FLOAT, m.data());
    }
    gl::TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, GLint(mips.size()));
    check_gl("uploading mip levels");
    return t;
}

std::string with_texture_filter(std::string src) {
    const std::string mark = "#include_texture_filter";
    const auto at = src.find(mark);
    if (at == std::string::npos) throw Error("reference shader: no " + mark + " line");
    return src.replace(at, mark.size(), load_shader_file("texture_filter.glsl"));
}

unsigned scene_sampler(const scene::Sampler& s) {
    auto wrap = [](scene::Wrap w) {
        return w == scene::Wrap::ClampToEdge ? GL_CLAMP_TO_EDGE : w == scene::Wrap::MirroredRepeat ? GL_MIRRORED_REPEAT : GL_REPEAT;
    };
    const bool near = s.min == scene::Filter::Nearest;
    GLint min = near ? GL_NEAREST : GL_LINEAR;
    if (s.mip == scene::MipFilter::Nearest) min = near ? GL_NEAREST_MIPMAP_NEAREST : GL_LINEAR_MIPMAP_NEAREST;
    if (s.mip == scene::MipFilter::Linear) min = near ? GL_NEAREST_MIPMAP_LINEAR : GL_LINEAR_MIPMAP_LINEAR;
    GLuint id = 0;
    gl::GenSamplers(1, &id);
    gl::SamplerParameteri(id, GL_TEXTURE_MIN_FILTER, min);
    gl::SamplerParameteri(id, GL_TEXTURE_MAG_FILTER, s.mag == scene::Filter::Nearest ? GL_NEAREST : GL_LINEAR);
    gl::SamplerParameteri(id, GL_TEXTURE_WRAP_S, wrap(s.wrap_s));
    gl::SamplerParameteri(id, GL_TEXTURE_WRAP_T, wrap(s.wrap_t));
    return id;
}

Texture::~Texture() {
    if (id_) gl::DeleteTextures(1, &id_);
}

Texture& Texture::operator=(Texture&& o) noexcept {
    if (this != &o) {
        if (id_) gl::DeleteTextures(1, &id_);
        id_ = o.id_;
        w_ = o.w_;
        h_ = o.h_;
        c_ = o.c_;
        o.id_ = 0;
    }
    return *this;
}

VertexBuffers::~VertexBuffers() {
    if (!ids.empty()) gl::DeleteBuffers(GLsizei(ids.size()), ids.data());
}

void VertexBuffers::attrib_floats(unsigned location, const void* data, std::size_t bytes, int components) {
    GLuint b = 0;
    gl::GenBuffers(1, &b);
    ids.push_back(b);
    gl::BindBuffer(GL_ARRAY_BUFFER, b);
    gl::BufferData(GL_ARRAY_BUFFER, GLsizeiptr(bytes), data, GL_STATIC_DRAW);
    gl::EnableVertexAttribArray(location);
    gl::VertexAttribPointer(location, components, GL_FLOAT, GL_FALSE, 0, nullptr);
}

ImageF read_texture(const Texture& t) {
    Fbo& f = fbo_state();
    gl::BindFramebuffer(GL_FRAMEBUFFER, f.fbo);
    gl::FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, t.id(), 0);
    gl::ReadBuffer(GL_COLOR_ATTACHMENT0);
    ImageF img(t.width(), t.height(), t.channels());
    gl::ReadPixels(0, 0, t.width(), t.height(), pixel_format(t.channels()), GL_FLOAT, img.data());
    check_gl("glReadPixels(GL_FLOAT)");
    return img;
}

unsigned program(const std::string& vertex, const std::string& fragment, const std::string& what) {
    context();
    static std::unordered_map<std::string, GLuint> cache;
    const std::string key = vertex + '\x01' + fragment;
    if (auto it = cache.find(key); it != cache.end()) return it->second;
    GLuint vs = compile(GL_VERTEX_SHADER, vertex, what + " (vertex)");
    GLuint fs = 0;
    try {
        fs = compile(GL_FRAGMENT_SHADER, fragment, what + " (fragment)");
    } catch (...) {
        gl::DeleteShader(vs);
        throw;
    }
    GLuint p = gl::CreateProgram();
    gl::AttachShader(p, vs);
    gl::AttachShader(p, fs);
    gl::LinkProgram(p);
    gl::DeleteShader(vs);
    gl::DeleteShader(fs);
    GLint ok = 0;
    gl::GetProgramiv(p, GL_LINK_STATUS, &ok);
    if (!ok) {
        std::string log = shader_log(p, true);
        gl::DeleteProgram(p);
        throw Error("GLSL link error in " + what + ":\n" + log);
    }
    cache.emplace(key, p);
    return p;
}

void set_uniform(unsigned prog, const std::string& name, const UniformValue& v) {
    GLint loc = gl::GetUniformLocation(prog, name.c_str());
    if (loc < 0) return;
    std::visit(
        [&](auto&& x) {
            using T = std::decay_t<decltype(x)>;
            if constexpr (std::is_same_v<T, float>) gl::Uniform1f(loc, x);
            else if constexpr (std::is_same_v<T, int>) gl::Uniform1i(loc, x);
            else if constexpr (std::is_same_v<T, bool>) gl::Uniform1i(loc, x ? 1 : 0);
            else if constexpr (std::is_same_v<T, glm::vec2>) gl::Uniform2f(loc, x.x, x.y);
            else if constexpr (std::is_same_v<T, glm::vec3>) gl::Uniform3f(loc, x.x, x.y, x.z);
            else if constexpr (std::is_same_v<T, glm::vec4>) gl::Uniform4f(loc, x.x, x.y, x.z, x.w);
            else if constexpr (std::is_same_v<T, glm::ivec2>) gl::Uniform2i(loc, x.x, x.y);
            else if constexpr (std::is_same_v<T, glm::mat4>) gl::UniformMatrix4fv(loc, 1, GL_FALSE, glm::value_ptr(x));
        },
        v);
}

Texture run_pass_texture(const Pass& pass) {
    context();
    if (pass.channels < 1 || pass.channels > 4) throw Error("pass " + pass.name + ": channels must be 1..4");
    Texture out(pass.width, pass.height, pass.channels);
    GLuint prog = program(kFullscreenVertex, pass.fragment, "pass " + pass.name);
    Fbo& f = fbo_state();
    gl::BindFramebuffer(GL_FRAMEBUFFER, f.fbo);
    gl::FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, out.id(), 0);
    const GLenum buf = GL_COLOR_ATTACHMENT0;
    gl::DrawBuffers(1, &buf);
    if (gl::CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw Error("pass " + pass.name + ": float framebuffer incomplete");
    gl::Viewport(0, 0, pass.width, pass.height);
    gl::Disable(GL_DEPTH_TEST);
    gl::Disable(GL_BLEND);
    gl::Disable(GL_CULL_FACE);
    gl::UseProgram(prog);

    static std::vector<GLuint> samplers;
    int unit = 0;
    for (auto& [name, in] : pass.inputs) {
        if (!in.texture || !in.texture->valid()) throw Error("pass " + pass.name + ": input '" + name + "' has no texture");
        if (unit >= int(samplers.size())) {
            GLuint s = 0;
            gl::GenSamplers(1, &s);
            samplers.push_back(s);
        }
        GLuint s = samplers[unit];
        const GLint filt = in.filter == Filter::Linear ? GL_LINEAR : GL_NEAREST;
        const GLint wrap = in.wrap == Wrap::Mirror ? GL_MIRRORED_REPEAT : GL_CLAMP_TO_EDGE;
        gl::SamplerParameteri(s, GL_TEXTURE_MIN_FILTER, filt);
        gl::SamplerParameteri(s, GL_TEXTURE_MAG_FILTER, filt);
        gl::SamplerParameteri(s, GL_TEXTURE_WRAP_S, wrap);
        gl::SamplerParameteri(s, GL_TEXTURE_WRAP_T, wrap);
        gl::ActiveTexture(GL_TEXTURE0 + unit);
        gl::BindTexture(GL_TEXTURE_2D, in.texture->id());
        gl::BindSampler(unit, s);
        set_uniform(prog, name, unit);
        ++unit;
    }
    for (auto& [name, v] : pass.uniforms) set_uniform(prog, name, v);
    set_uniform(prog, "u_out_size", glm::ivec2(pass.width, pass.height));
    gl::BindVertexArray(f.vao);
    gl::DrawArrays(GL_TRIANGLES, 0, 3);
    check_gl(("pass " + pass.name).c_str());
    return out;
}

ImageF run_pass(const Pass& pass) { return read_texture(run_pass_texture(pass)); }

std::string shader_dir() {
    if (const char* e = std::getenv("AQ_REFERENCE_SHADER_DIR")) return e;
    return AQ_REFERENCE_SHADER_DIR;
}

bool shader_file_exists(const std::string& name) { return std::filesystem::exists(shader_dir() + "/" + name); }

std::string load_shader_file(const std::string& name) {
    const std::string path = shader_dir() + "/" + name;
    std::ifstream f(path);
    if (!f) throw Error("GLSL file not found: " + path);
    std::ostringstream s;
    s << f.rdbuf();
    return s.str();
}

std::string assemble_fragment(const std::string& body, const std::vector<std::string>& defines) {
    std::string src = "#version 450 core\n";
    for (auto& d : defines) src += "#define " + d + "\n";
    // Diagnostic: exact-weight bilinear taps instead of the texture unit's (common.glsl).
    if (const char* e = std::getenv("AQ_REFERENCE_EXACT_BILINEAR"); e && std::string(e) == "1")
        src += "#define AQ_EXACT_BILINEAR 1\n";
    src += "#line 1 1\n" + load_shader_file("common.glsl");
    src += "\n#line 1 2\n" + body;
    return src;
}

void finish() { gl::Finish(); }

}  // namespace aq::ref
