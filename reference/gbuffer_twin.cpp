// reference/gbuffer_twin.cpp — draws a scene through the GLSL G-buffer twin.
#include "reference/gbuffer_twin.h"

#include <cmath>

#include "raster/vertex.h"
#include "reference/gl_api.h"
#include "reference/gl_context.h"
#include "reference/gl_runner.h"

namespace aq::ref {

namespace {

constexpr int kMaxLights = 8;  // matches gbuffer.frag.glsl

glm::vec3 normalize3(glm::vec3 v) {
    const float l2 = (v.x * v.x + v.y * v.y) + v.z * v.z;
    return l2 > 0.0f ? v * (1.0f / std::sqrt(l2)) : v;
}

struct Samplers {
    std::vector<GLuint> ids;
    ~Samplers() {
        if (!ids.empty()) gl::DeleteSamplers(GLsizei(ids.size()), ids.data());
    }
    GLuint make(const scene::Sampler& s) {
        ids.push_back(scene_sampler(s));
        return ids.back();
    }
};

}  // namespace

Targets render_gbuffer_gl(const scene::Scene& sc, const scene::Camera& cam, const raster::RenderSettings& s) {
    std::string why;
    if (!GlContext::shared(&why)) throw Error("render_gbuffer_gl: no OpenGL context: " + why);
    if (s.ssaa != 1) throw Error("render_gbuffer_gl: ssaa must be 1");
    const int W = s.width, H = s.height;
    check_image_size(W, H, "render_gbuffer_gl");

    // Targets: 7 RGBA32F colour attachments + a 32-bit float depth buffer.
    std::vector<Texture> att;
    for (int k = 0; k < 7; ++k) att.emplace_back(W, H, 4);
    GLuint fbo = 0, depth_rb = 0, vao = 0;
    gl::GenFramebuffers(1, &fbo);
    gl::BindFramebuffer(GL_FRAMEBUFFER, fbo);
    GLenum bufs[7];
    for (int k = 0; k < 7; ++k) {
        gl::FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + k, GL_TEXTURE_2D, att[k].id(), 0);
        bufs[k] = GL_COLOR_ATTACHMENT0 + k;
    }
    gl::GenRenderbuffers(1, &depth_rb);
    gl::BindRenderbuffer(GL_RENDERBUFFER, depth_rb);
    gl::RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, W, H);
    gl::FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_rb);
    gl::DrawBuffers(7, bufs);
    if (gl::CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw Error("render_gbuffer_gl: MRT framebuffer incomplete");
    gl::Viewport(0, 0, W, H);
    const float zero[4] = {0, 0, 0, 0};
    for (int k = 0; k < 6; ++k) gl::ClearBufferfv(GL_COLOR, k, zero);
    const float misc_bg[4] = {cam.zfar, 0, 0, 0};  // background depth = zfar, id 0
    gl::ClearBufferfv(GL_COLOR, 6, misc_bg);
    const float one = 1.0f;
    gl::ClearBufferfv(GL_DEPTH, 0, &one);
    gl::Enable(GL_DEPTH_TEST);
    gl::DepthFunc(GL_LESS);  // strict: the first triangle in submission order keeps a tie
    gl::DepthMask(GL_TRUE);
    gl::Disable(GL_BLEND);
    // The y flip in the vertex shader mirrors the winding: glTF's counter-clockwise front faces
    // are clockwise in GL window space.
    gl::FrontFace(GL_CW);
    if (s.cull_backfaces) gl::CullFace(GL_BACK);

    const GLuint prog = program(load_shader_file("gbuffer.vert.glsl"), with_texture_filter(load_shader_file("gbuffer.frag.glsl")),
                                "G-buffer twin");
    gl::UseProgram(prog);
    gl::GenVertexArrays(1, &vao);
    gl::BindVertexArray(vao);

    const float aspect = float(W) / float(H);
    set_uniform(prog, "u_projection", raster::projection_matrix(cam, aspect));
    set_uniform(prog, "u_perspective", !cam.orthographic);
    set_uniform(prog, "u_tremor", s.tremor.enabled && s.tremor.tremor_px != 0.0f);
    set_uniform(prog, "u_tremor_px", s.tremor.tremor_px);
    set_uniform(prog, "u_front", s.tremor.front);
    set_uniform(prog, "u_speed", s.tremor.speed);
    set_uniform(prog, "u_frequency", s.tremor.frequency);
    set_uniform(prog, "u_time", float(s.frame) / s.fps);
    set_uniform(prog, "u_bleed_displacement", s.bleed_displacement);
    set_uniform(prog, "u_size", glm::vec2(float(W), float(H)));
    set_uniform(prog, "u_ambient", sc.ambient);
    set_uniform(prog, "u_substrate", s.substrate_color);
    set_uniform(prog, "u_object_space_turbulence", s.turbulence == raster::RenderSettings::Turbulence::ObjectSpace);
    set_uniform(prog, "u_working_linear", s.working_space == WorkingSpace::Linear);
    const glm::mat3 v3(cam.view);
    int nl = 0;
    for (const scene::Light& l : sc.lights) {
        if (nl == kMaxLights) throw Error("render_gbuffer_gl: more than 8 lights");
        set_uniform(prog, "u_light_dir[" + std::to_string(nl) + "]", normalize3(v3 * l.direction));
        set_uniform(prog, "u_light_radiance[" + std::to_string(nl) + "]", l.color * l.intensity);
        ++nl;
    }
    if (nl == 0) {  // raster::default_view_light()
        set_uniform(prog, "u_light_dir[0]", normalize3(glm::vec3(-0.5f, 0.5f, 1.0f)));
        set_uniform(prog, "u_light_radiance[0]", glm::vec3(1.0f));
        nl = 1;
    }
    set_uniform(prog, "u_num_lights", nl);
    set_uniform(prog, "s_base", 0);
    set_uniform(prog, "s_normal", 1);
    for (int k = 0; k < 4; ++k) set_uniform(prog, "s_ctrl" + std::to_string(k), 2 + k);

    // Scene textures, uploaded once.
    std::vector<Texture> tex(sc.textures.size());
    for (std::size_t i = 0; i < sc.textures.size(); ++i)
        if (!sc.textures[i].empty()) tex[i] = Texture::upload(sc.textures[i].level0(), sc.textures[i].all_mips());
    Samplers samplers;
    auto bind = [&](int unit, const scene::TextureRef& r) {
        const bool ok = r.texture >= 0 && r.texture < int(tex.size()) && tex[r.texture].valid();
        gl::ActiveTexture(GL_TEXTURE0 + unit);
        gl::BindTexture(GL_TEXTURE_2D, ok ? tex[r.texture].id() : 0);
        gl::BindSampler(unit, ok ? samplers.make(r.sampler) : 0);
        return ok;
    };

    const scene::Material default_material;
    for (const scene::Instance& inst : sc.instances) {
        if (inst.mesh < 0 || inst.mesh >= int(sc.meshes.size())) continue;
        const glm::mat4 mv = cam.view * inst.world;
        set_uniform(prog, "u_model_view", mv);
        const glm::mat3 nm = glm::transpose(glm::inverse(glm::mat3(mv)));
        GLint loc = gl::GetUniformLocation(prog, "u_normal_matrix");
        gl::UniformMatrix3fv(loc, 1, GL_FALSE, &nm[0][0]);
        set_uniform(prog, "u_object_id", float(inst.object_id));
        for (const scene::Primitive& p : sc.meshes[inst.mesh].primitives) {
            const std::size_t n = p.positions.size();
            if (n == 0 || p.indices.empty()) continue;
            const scene::Material& m =
                p.material >= 0 && p.material < int(sc.materials.size()) ? sc.materials[p.material] : default_material;
            VertexBuffers b;
            b.attrib(0, p.positions, 3);
            b.attrib(1, p.normals.size() == n ? p.normals : std::vector<glm::vec3>(n, glm::vec3(0, 0, 1)), 3);
            const bool has_tan = p.tangents.size() == n && m.normal_texture.texture >= 0;
            b.attrib(2, has_tan ? p.tangents : std::vector<glm::vec4>(n, glm::vec4(0.0f)), 4);
            const bool has_uv = p.uv0.size() == n;
            b.attrib(3, has_uv ? p.uv0 : std::vector<glm::vec2>(n, glm::vec2(0.0f)), 2);
            b.attrib(4, p.colors.size() == n ? p.colors : std::vector<glm::vec4>(n, glm::vec4(1.0f)), 4);
            for (int k = 0; k < 4; ++k)
                b.attrib(GLuint(5 + k), p.control[k].size() == n ? p.control[k] : std::vector<glm::vec4>(n, glm::vec4(0.0f)), 4);
            GLuint ebo = 0;
            gl::GenBuffers(1, &ebo);
            b.ids.push_back(ebo);
            gl::BindBuffer(GL_ELEMENT_ARRAY_BUFFER, ebo);
            gl::BufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(p.indices.size() * 4), p.indices.data(), GL_STATIC_DRAW);

            const auto& wc = m.wc;
            set_uniform(prog, "u_base_color", m.base_color);
            set_uniform(prog, "u_linear_color", m.linear_color);
            set_uniform(prog, "u_has_uv", has_uv);
            set_uniform(prog, "u_has_tangent", has_tan);
            set_uniform(prog, "u_double_sided", m.double_sided);
            set_uniform(prog, "u_alpha_mask", m.alpha_mode == scene::AlphaMode::Mask);
            set_uniform(prog, "u_alpha_cutoff", m.alpha_cutoff);
            set_uniform(prog, "u_has_base_tex", bind(0, m.base_color_texture));
            set_uniform(prog, "u_has_normal_tex", bind(1, m.normal_texture));
            set_uniform(prog, "u_normal_scale", m.normal_texture.scale);
            for (int k = 0; k < 4; ++k) {
                set_uniform(prog, "u_has_ctrl_tex[" + std::to_string(k) + "]", bind(2 + k, wc.control_texture[k]));
                set_uniform(prog, "u_ctrl_const[" + std::to_string(k) + "]", wc.control[k]);
            }
            set_uniform(prog, "u_bleed_const", wc.control[scene::kCtrlAbstraction].b);
            set_uniform(prog, "u_dilute", wc.dilute);
            set_uniform(prog, "u_cangiante", wc.cangiante);
            set_uniform(prog, "u_diffuse_factor", wc.diffuse_factor);
            set_uniform(prog, "u_dilute_area", wc.dilute_area);
            set_uniform(prog, "u_shade_wrap", wc.shade_wrap);
            set_uniform(prog, "u_shade_color", wc.shade_color);
            set_uniform(prog, "u_specular", wc.specular);
            set_uniform(prog, "u_specular_power", wc.specular_power);
            if (s.cull_backfaces && !m.double_sided) gl::Enable(GL_CULL_FACE);
            else gl::Disable(GL_CULL_FACE);
            gl::DrawElements(GL_TRIANGLES, GLsizei(p.indices.size()), GL_UNSIGNED_INT, nullptr);
            check_gl("G-buffer twin draw");
        }
    }
    gl::Disable(GL_DEPTH_TEST);
    gl::Disable(GL_CULL_FACE);
    gl::FrontFace(GL_CCW);
    gl::BindVertexArray(0);
    gl::DeleteVertexArrays(1, &vao);
    gl::BindFramebuffer(GL_FRAMEBUFFER, 0);
    gl::DeleteFramebuffers(1, &fbo);
    gl::DeleteRenderbuffers(1, &depth_rb);
    for (int u = 0; u < 6; ++u) gl::BindSampler(u, 0);

    std::vector<ImageF> img;
    for (auto& t : att) img.push_back(read_texture(t));
    Targets out;
    out.set(target::kColor, img[0]);
    out.set(target::kCtrlPigment, img[1]);
    out.set(target::kCtrlSubstrate, img[2]);
    out.set(target::kCtrlEdge, img[3]);
    out.set(target::kCtrlAbstraction, img[4]);
    ImageF normal(W, H, 3), depth(W, H, 1), id(W, H, 1), diff(W, H, 1), spec(W, H, 1);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            for (int c = 0; c < 3; ++c) normal.at(x, y, c) = img[5].at(x, y, c);
            depth.at(x, y, 0) = img[6].at(x, y, 0);
            id.at(x, y, 0) = img[6].at(x, y, 1);
            diff.at(x, y, 0) = img[6].at(x, y, 2);
            spec.at(x, y, 0) = img[6].at(x, y, 3);
        }
    out.set(target::kNormal, std::move(normal));
    out.set(target::kDepthLinear, std::move(depth));
    out.set(target::kObjectId, std::move(id));
    out.set(target::kDiffuse, std::move(diff));
    out.set(target::kSpecular, std::move(spec));
    // The twin produces exactly the rasterizer's layout (core/targets.h kGBufferLayout).
    for (const target::GBufferTarget& g : target::kGBufferLayout)
        if (!out.has(g.name) || out.get(g.name).channels() != g.channels)
            throw Error(std::string("gbuffer twin: target '") + g.name + "' missing or not " +
                        std::to_string(g.channels) + " channels");
    return out;
}

}  // namespace aq::ref
