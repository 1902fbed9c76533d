// reference/pass_twin.cpp — draws a scene through the LD06 raster-pass twin.
#include "reference/pass_twin.h"

#include <cmath>

#include "raster/vertex.h"
#include "reference/gl_api.h"
#include "reference/gl_context.h"
#include "reference/gl_runner.h"

namespace aq::ref {

namespace {

GLuint linear_sampler(GLint wrap) {
    GLuint id = 0;
    gl::GenSamplers(1, &id);
    gl::SamplerParameteri(id, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    gl::SamplerParameteri(id, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    gl::SamplerParameteri(id, GL_TEXTURE_WRAP_S, wrap);
    gl::SamplerParameteri(id, GL_TEXTURE_WRAP_T, wrap);
    return id;
}

//! A twin's fragment shader with ld06_common.glsl in place of its `#include_ld06_common` line.
std::string ld06_fragment(const std::string& file) {
    std::string src = load_shader_file(file);
    const std::string mark = "#include_ld06_common";
    const auto at = src.find(mark);
    if (at == std::string::npos) throw Error("reference shader " + file + ": no " + mark + " line");
    return src.replace(at, mark.size(), load_shader_file("ld06_common.glsl"));
}

}  // namespace

ImageF render_triangle_pass_gl(const raster::PassScene& ps, const raster::TrianglePass& p) {
    std::string why;
    if (!GlContext::shared(&why)) throw Error("render_triangle_pass_gl: no OpenGL context: " + why);
    if (!ps.scene) throw Error("render_triangle_pass_gl: no scene");
    const raster::PassViewSetup view = raster::pass_view(ps, p.view, p.scale);
    const int W = view.width, H = view.height;
    const scene::Scene& sc = *ps.scene;

    Texture target(W, H, 4);
    GLuint fbo = 0, depth_rb = 0, vao = 0;
    gl::GenFramebuffers(1, &fbo);
    gl::BindFramebuffer(GL_FRAMEBUFFER, fbo);
    gl::FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, target.id(), 0);
    gl::GenRenderbuffers(1, &depth_rb);
    gl::BindRenderbuffer(GL_RENDERBUFFER, depth_rb);
    gl::RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, W, H);
    gl::FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_rb);
    const GLenum buf = GL_COLOR_ATTACHMENT0;
    gl::DrawBuffers(1, &buf);
    if (gl::CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw Error("render_triangle_pass_gl: framebuffer incomplete");
    gl::Viewport(0, 0, W, H);
    const float bg = p.value == raster::PassValue::Depth ? 1.0f : 0.0f;
    const float clear[4] = {bg, 0, 0, 0};
    gl::ClearBufferfv(GL_COLOR, 0, clear);
    const float one = 1.0f;
    gl::ClearBufferfv(GL_DEPTH, 0, &one);
    if (p.test == raster::DepthTest::Binary) {
        gl::Enable(GL_DEPTH_TEST);
        gl::DepthFunc(GL_LESS);  // strict: the first fragment in submission order keeps a tie
        gl::DepthMask(GL_TRUE);
    } else {
        gl::Disable(GL_DEPTH_TEST);
    }
    if (p.blend == raster::Blend::Add) {
        gl::Enable(GL_BLEND);
        gl::BlendFunc(GL_ONE, GL_ONE);
    } else if (p.blend == raster::Blend::Over) {
        gl::Enable(GL_BLEND);
        gl::BlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    } else {
        gl::Disable(GL_BLEND);
    }
    gl::FrontFace(GL_CW);  // the y flip mirrors the winding (as the G-buffer twin)
    gl::Disable(GL_CULL_FACE);

    const GLuint prog = program(load_shader_file("pass.vert.glsl"), with_texture_filter(ld06_fragment("pass.frag.glsl")), "raster pass twin");
    gl::UseProgram(prog);
    gl::GenVertexArrays(1, &vao);
    gl::BindVertexArray(vao);
    set_uniform(prog, "u_projection", raster::projection_matrix(view.camera, float(ps.width) / float(ps.height)));
    set_uniform(prog, "u_value", int(p.value));
    set_uniform(prog, "u_test", int(p.test));
    set_uniform(prog, "u_blend", int(p.blend));
    set_uniform(prog, "u_delta", p.delta);
    set_uniform(prog, "u_beta", p.beta);
    set_uniform(prog, "u_alpha", p.alpha);
    set_uniform(prog, "u_depth_near", view.depth_near);
    set_uniform(prog, "u_depth_far", view.depth_far);
    set_uniform(prog, "u_size", glm::vec2(float(W), float(H)));
    set_uniform(prog, "u_light_view", glm::normalize(glm::mat3(view.camera.view) * ps.light_dir));
    std::vector<GLuint> samplers = {linear_sampler(GL_CLAMP_TO_EDGE)};
    Texture depth_tex, shadow_tex;
    if (p.test != raster::DepthTest::Binary && p.depth_map) {
        gl::ActiveTexture(GL_TEXTURE1);
        depth_tex = Texture::upload(*p.depth_map);
        gl::BindTexture(GL_TEXTURE_2D, depth_tex.id());
        gl::BindSampler(1, samplers[0]);
        set_uniform(prog, "s_depth", 1);
    }
    if (p.value == raster::PassValue::Shadow && p.shadow_map) {
        const raster::PassViewSetup light = raster::pass_view(ps, raster::PassView::Light, 1.0f);
        gl::ActiveTexture(GL_TEXTURE2);
        shadow_tex = Texture::upload(*p.shadow_map);
        gl::BindTexture(GL_TEXTURE_2D, shadow_tex.id());
        gl::BindSampler(2, samplers[0]);
        set_uniform(prog, "s_shadow", 2);
        set_uniform(prog, "u_view_to_light", light.camera.view * glm::inverse(view.camera.view));
        set_uniform(prog, "u_light_mag", glm::vec2(light.camera.xmag, light.camera.ymag));
        set_uniform(prog, "u_light_near", light.depth_near);
        set_uniform(prog, "u_light_far", light.depth_far);
        set_uniform(prog, "u_shadow_test", int(p.shadow_test));
        set_uniform(prog, "u_shadow_delta", p.shadow_delta);
        set_uniform(prog, "u_shadow_beta", p.shadow_beta);
    }
    set_uniform(prog, "s_base", 0);
    set_uniform(prog, "s_intensity", 3);
    set_uniform(prog, "u_channel", p.channel);
    std::vector<Texture> tex(sc.textures.size());

    for (const scene::Instance& inst : sc.instances) {
        if (inst.mesh < 0 || inst.mesh >= int(sc.meshes.size())) continue;
        const glm::mat4 mv = view.camera.view * inst.world;
        set_uniform(prog, "u_model_view", mv);
        const glm::mat3 nm = glm::transpose(glm::inverse(glm::mat3(mv)));
        gl::UniformMatrix3fv(gl::GetUniformLocation(prog, "u_normal_matrix"), 1, GL_FALSE, &nm[0][0]);
        for (const scene::Primitive& prim : sc.meshes[std::size_t(inst.mesh)].primitives) {
            const bool foliage = scene::is_foliage(sc, inst, prim);
            if ((p.draw == raster::DrawSet::Foliage && !foliage) || (p.draw == raster::DrawSet::NonFoliage && foliage)) continue;
            const std::size_t n = prim.positions.size();
            if (n == 0 || prim.indices.size() < 3) continue;
            const scene::Material m =
                prim.material >= 0 && prim.material < int(sc.materials.size()) ? sc.materials[std::size_t(prim.material)] : scene::Material{};
            VertexBuffers b;
            b.attrib(0, prim.positions, 3);
            b.attrib(1, prim.normals.size() == n ? prim.normals : std::vector<glm::vec3>(n, glm::vec3(0, 0, 1)), 3);
            const bool has_uv = prim.uv0.size() == n;
            b.attrib(2, has_uv ? prim.uv0 : std::vector<glm::vec2>(n, glm::vec2(0.0f)), 2);
            b.attrib(3, prim.colors.size() == n ? prim.colors : std::vector<glm::vec4>(n, glm::vec4(1.0f)), 4);
            GLuint ebo = 0;
            gl::GenBuffers(1, &ebo);
            b.ids.push_back(ebo);
            gl::BindBuffer(GL_ELEMENT_ARRAY_BUFFER, ebo);
            gl::BufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(prim.indices.size() * 4), prim.indices.data(), GL_STATIC_DRAW);
            const bool mask = m.alpha_mode == scene::AlphaMode::Mask;
            bool has_tex = false;
            const int ti = m.base_color_texture.texture;
            if (mask && has_uv && ti >= 0 && ti < int(tex.size()) && !sc.textures[std::size_t(ti)].empty()) {
                gl::ActiveTexture(GL_TEXTURE0);  // before the upload: it binds to the active unit
                if (!tex[std::size_t(ti)].valid()) tex[std::size_t(ti)] = Texture::upload(sc.textures[std::size_t(ti)].level0(), sc.textures[std::size_t(ti)].all_mips());
                gl::BindTexture(GL_TEXTURE_2D, tex[std::size_t(ti)].id());
                samplers.push_back(scene_sampler(m.base_color_texture.sampler));
                gl::BindSampler(0, samplers.back());
                has_tex = true;
            }
            const int ii = m.intensity_texture.texture;
            const bool has_intensity = has_uv && ii >= 0 && ii < int(tex.size()) && !sc.textures[std::size_t(ii)].empty();
            if (has_intensity) {
                gl::ActiveTexture(GL_TEXTURE3);
                if (!tex[std::size_t(ii)].valid()) tex[std::size_t(ii)] = Texture::upload(sc.textures[std::size_t(ii)].level0(), sc.textures[std::size_t(ii)].all_mips());
                gl::BindTexture(GL_TEXTURE_2D, tex[std::size_t(ii)].id());
                samplers.push_back(scene_sampler(m.intensity_texture.sampler));
                gl::BindSampler(3, samplers.back());
            }
            set_uniform(prog, "u_has_intensity", has_intensity);
            set_uniform(prog, "u_alpha_mask", mask);
            set_uniform(prog, "u_alpha_cutoff", m.alpha_cutoff);
            set_uniform(prog, "u_base_alpha", m.base_color.a);
            set_uniform(prog, "u_has_base_tex", has_tex);
            gl::DrawElements(GL_TRIANGLES, GLsizei(prim.indices.size()), GL_UNSIGNED_INT, nullptr);
            check_gl("raster pass twin draw");
        }
    }
    gl::Disable(GL_DEPTH_TEST);
    gl::Disable(GL_BLEND);
    gl::FrontFace(GL_CCW);
    gl::BindVertexArray(0);
    gl::DeleteVertexArrays(1, &vao);
    gl::BindFramebuffer(GL_FRAMEBUFFER, 0);
    gl::DeleteFramebuffers(1, &fbo);
    gl::DeleteRenderbuffers(1, &depth_rb);
    for (int u = 0; u < 4; ++u) gl::BindSampler(GLuint(u), 0);
    gl::DeleteSamplers(GLsizei(samplers.size()), samplers.data());

    const ImageF rgba = read_texture(target);
    ImageF out(W, H, 1);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const float v = rgba.at(x, y, 0);
            out.at(x, y, 0) = p.blend == raster::Blend::Add ? std::min(v, 1.0f) : v;
        }
    return out;
}

std::array<ImageF, 3> render_particles_gl(const raster::PassScene& ps, const std::vector<raster::Particle>& particles,
                                          const raster::ParticleParams& p) {
    std::string why;
    if (!GlContext::shared(&why)) throw Error("render_particles_gl: no OpenGL context: " + why);
    if (!p.depth_map || p.depth_map->channels() != 1) throw Error("render_particles_gl: needs a 1-channel depth map");
    const raster::PassViewSetup view = raster::pass_view(ps, raster::PassView::Camera, p.scale);
    const int W = view.width, H = view.height;
    Texture target(W, H, 4);
    GLuint fbo = 0, vao = 0;
    gl::GenFramebuffers(1, &fbo);
    gl::BindFramebuffer(GL_FRAMEBUFFER, fbo);
    gl::FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, target.id(), 0);
    const GLenum buf = GL_COLOR_ATTACHMENT0;
    gl::DrawBuffers(1, &buf);
    if (gl::CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw Error("render_particles_gl: framebuffer incomplete");
    gl::Viewport(0, 0, W, H);
    const float zero[4] = {0, 0, 0, 0};
    gl::ClearBufferfv(GL_COLOR, 0, zero);
    gl::Disable(GL_DEPTH_TEST);
    gl::Enable(GL_BLEND);
    gl::BlendFunc(GL_ONE, GL_ONE);
    gl::Enable(GL_PROGRAM_POINT_SIZE);
    const GLuint prog = program(load_shader_file("particles.vert.glsl"), ld06_fragment("particles.frag.glsl"), "particle twin");
    gl::UseProgram(prog);
    gl::GenVertexArrays(1, &vao);
    gl::BindVertexArray(vao);
    set_uniform(prog, "u_view", view.camera.view);
    set_uniform(prog, "u_projection", raster::projection_matrix(view.camera, float(ps.width) / float(ps.height)));
    set_uniform(prog, "u_depth_near", view.depth_near);
    set_uniform(prog, "u_depth_far", view.depth_far);
    set_uniform(prog, "u_size_scale", p.size_scale);
    set_uniform(prog, "u_size_bias", p.size_bias);
    set_uniform(prog, "u_width", float(W));
    set_uniform(prog, "u_test", int(p.test));
    set_uniform(prog, "u_delta", p.delta);
    set_uniform(prog, "u_beta", p.beta);
    set_uniform(prog, "u_shape", p.shape);
    set_uniform(prog, "u_size", glm::vec2(float(W), float(H)));
    gl::ActiveTexture(GL_TEXTURE1);
    Texture depth_tex = Texture::upload(*p.depth_map);
    const GLuint smp = linear_sampler(GL_CLAMP_TO_EDGE);
    gl::BindSampler(1, smp);
    set_uniform(prog, "s_depth", 1);
    std::vector<glm::vec3> pos;
    std::vector<float> cls;
    for (const raster::Particle& q : particles) {
        pos.push_back(q.position);
        cls.push_back(float(q.cls));
    }
    {
        VertexBuffers b;
        b.attrib(0, pos, 3);
        b.attrib(1, cls, 1);
        if (!pos.empty()) gl::DrawArrays(GL_POINTS, 0, GLsizei(pos.size()));
        check_gl("particle twin draw");
    }
    gl::Disable(GL_BLEND);
    gl::Disable(GL_PROGRAM_POINT_SIZE);
    gl::BindVertexArray(0);
    gl::DeleteVertexArrays(1, &vao);
    gl::BindFramebuffer(GL_FRAMEBUFFER, 0);
    gl::DeleteFramebuffers(1, &fbo);
    gl::BindSampler(1, 0);
    gl::DeleteSamplers(1, &smp);
    const ImageF rgba = read_texture(target);
    std::array<ImageF, 3> out = {ImageF(W, H, 1), ImageF(W, H, 1), ImageF(W, H, 1)};
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            for (int k = 0; k < 3; ++k) out[std::size_t(k)].at(x, y, 0) = std::min(rgba.at(x, y, k), 1.0f);
    return out;
}

ImageF render_strokes_gl(const raster::PassScene& ps, const std::vector<raster::Stroke>& strokes,
                         const raster::StrokeParams& p) {
    std::string why;
    if (!GlContext::shared(&why)) throw Error("render_strokes_gl: no OpenGL context: " + why);
    const raster::PassViewSetup view = raster::pass_view(ps, raster::PassView::Camera, p.scale);
    const int W = view.width, H = view.height;
    const float half = 0.5f * p.width_px * float(W) / float(raster::kLd06SizeReferenceStrokes);
    Texture acc(W, H, 4), one(W, H, 4);
    GLuint fbo[2] = {0, 0}, depth_rb = 0, vao = 0, empty_vao = 0;  // empty_vao: the composite reads no attribute
    gl::GenFramebuffers(2, fbo);
    gl::BindFramebuffer(GL_FRAMEBUFFER, fbo[0]);  // the accumulated strokes
    gl::FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, acc.id(), 0);
    const GLenum buf = GL_COLOR_ATTACHMENT0;
    gl::DrawBuffers(1, &buf);
    const float zero[4] = {0, 0, 0, 0};
    gl::Viewport(0, 0, W, H);
    gl::ClearBufferfv(GL_COLOR, 0, zero);
    gl::BindFramebuffer(GL_FRAMEBUFFER, fbo[1]);  // one stroke, with its nearest-segment depth
    gl::FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, one.id(), 0);
    gl::GenRenderbuffers(1, &depth_rb);
    gl::BindRenderbuffer(GL_RENDERBUFFER, depth_rb);
    gl::RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, W, H);
    gl::FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_rb);
    gl::DrawBuffers(1, &buf);
    if (gl::CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw Error("render_strokes_gl: framebuffer incomplete");

    const GLuint draw = program(load_shader_file("strokes.vert.glsl"), ld06_fragment("strokes.frag.glsl"), "stroke twin");
    static const char* kCompositeVertex = R"(#version 450 core
void main() {
    vec2 c = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    gl_Position = vec4(c * 2.0 - 1.0, 0.0, 1.0);
})";
    static const char* kCompositeFragment = R"(#version 450 core
uniform sampler2D s_stroke;
layout(location = 0) out vec4 o_color;
void main() {
    float a = texelFetch(s_stroke, ivec2(gl_FragCoord.xy), 0).r;
    o_color = vec4(a);  // blended ONE, ONE_MINUS_SRC_ALPHA: dst = a + dst (1 - a)
})";
    const GLuint composite = program(kCompositeVertex, kCompositeFragment, "stroke twin composite");
    gl::GenVertexArrays(1, &vao);
    gl::GenVertexArrays(1, &empty_vao);
    const GLuint smp = linear_sampler(GL_CLAMP_TO_EDGE);
    Texture depth_tex;
    const bool has_depth = p.depth_map && !p.depth_map->empty() && p.depth_map->channels() == 1;
    if (has_depth) depth_tex = Texture::upload(*p.depth_map);
    gl::UseProgram(draw);
    set_uniform(draw, "u_projection", raster::projection_matrix(view.camera, float(ps.width) / float(ps.height)));
    set_uniform(draw, "u_size", glm::vec2(float(W), float(H)));
    set_uniform(draw, "u_half", half);
    set_uniform(draw, "u_r2", half * half);
    set_uniform(draw, "u_ortho", view.camera.orthographic);
    set_uniform(draw, "u_depth_near", view.depth_near);
    set_uniform(draw, "u_depth_far", view.depth_far);
    set_uniform(draw, "u_test", int(p.test));
    set_uniform(draw, "u_has_depth", has_depth);
    set_uniform(draw, "u_delta", p.delta);
    set_uniform(draw, "u_beta", p.beta);
    set_uniform(draw, "u_alpha", p.alpha);
    set_uniform(draw, "u_fade_near", p.fade_near);
    set_uniform(draw, "u_fade_far", p.fade_far);
    set_uniform(draw, "u_nv_lo", p.nv_lo);
    set_uniform(draw, "u_nv_hi", p.nv_hi);
    set_uniform(draw, "u_nl_lo", p.nl_lo);
    set_uniform(draw, "u_nl_hi", p.nl_hi);
    set_uniform(draw, "u_light_view", glm::normalize(glm::mat3(view.camera.view) * ps.light_dir));
    set_uniform(draw, "s_depth", 1);
    gl::UseProgram(composite);
    set_uniform(composite, "s_stroke", 2);
    const glm::mat3 rot(view.camera.view);
    const float znear = view.camera.znear;
    const float one_depth = 1.0f;
    for (const raster::Stroke& s : strokes) {
        // Segments in view space, clipped at the near plane (perspective), non-finite ones dropped.
        std::vector<glm::vec3> pa, pb, na, nb;
        std::vector<glm::vec2> corner;
        std::vector<float> has_n;
        const bool normals = s.normals.size() == s.points.size();
        for (std::size_t i = 0; i + 1 < s.points.size(); ++i) {
            glm::vec3 a(view.camera.view * glm::vec4(s.points[i], 1.0f)), b(view.camera.view * glm::vec4(s.points[i + 1], 1.0f));
            glm::vec3 an = normals ? rot * s.normals[i] : glm::vec3(0.0f), bn = normals ? rot * s.normals[i + 1] : glm::vec3(0.0f);
            bool finite = true;
            for (int c = 0; c < 3; ++c) finite = finite && std::isfinite(a[c]) && std::isfinite(b[c]) && std::isfinite(an[c]) && std::isfinite(bn[c]);
            if (!finite) continue;
            if (!view.camera.orthographic) {
                if (-a.z < znear && -b.z < znear) continue;
                if (-a.z < znear || -b.z < znear) {
                    const float t = (znear + a.z) / (a.z - b.z);  // where -z reaches znear
                    const glm::vec3 c = a + (b - a) * t, cn = an + (bn - an) * t;
                    if (-a.z < znear) a = c, an = cn;
                    else b = c, bn = cn;
                }
            }
            const float la = glm::length(an), lb = glm::length(bn);
            const bool hn = normals && la > 0.0f && lb > 0.0f;
            for (glm::vec2 q : {glm::vec2(0, 0), glm::vec2(1, 0), glm::vec2(1, 1), glm::vec2(0, 0), glm::vec2(1, 1), glm::vec2(0, 1)}) {
                pa.push_back(a);
                pb.push_back(b);
                na.push_back(hn ? an / la : glm::vec3(0.0f));
                nb.push_back(hn ? bn / lb : glm::vec3(0.0f));
                corner.push_back(q);
                has_n.push_back(hn ? 1.0f : 0.0f);
            }
        }
        if (pa.empty()) continue;
        // 1. This stroke alone: the nearest segment per pixel wins the depth test.
        gl::BindFramebuffer(GL_FRAMEBUFFER, fbo[1]);
        gl::ClearBufferfv(GL_COLOR, 0, zero);
        gl::ClearBufferfv(GL_DEPTH, 0, &one_depth);
        gl::Enable(GL_DEPTH_TEST);
        gl::DepthFunc(GL_LESS);
        gl::DepthMask(GL_TRUE);
        gl::Disable(GL_BLEND);
        gl::BindVertexArray(vao);
        gl::UseProgram(draw);
        set_uniform(draw, "u_hatching", s.light_dependent);
        if (has_depth) {
            gl::ActiveTexture(GL_TEXTURE1);
            gl::BindTexture(GL_TEXTURE_2D, depth_tex.id());
            gl::BindSampler(1, smp);
        }
        {
            VertexBuffers vb;
            vb.attrib(0, pa, 3);
            vb.attrib(1, pb, 3);
            vb.attrib(2, na, 3);
            vb.attrib(3, nb, 3);
            vb.attrib(4, corner, 2);
            vb.attrib(5, has_n, 1);
            gl::DrawArrays(GL_TRIANGLES, 0, GLsizei(pa.size()));
            check_gl("stroke twin draw");
        }
        // 2. Composited over the strokes before it.
        gl::BindFramebuffer(GL_FRAMEBUFFER, fbo[0]);
        gl::Disable(GL_DEPTH_TEST);
        gl::Enable(GL_BLEND);
        gl::BlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
        gl::BindVertexArray(empty_vao);
        gl::UseProgram(composite);
        gl::ActiveTexture(GL_TEXTURE2);
        gl::BindTexture(GL_TEXTURE_2D, one.id());
        gl::DrawArrays(GL_TRIANGLES, 0, 3);
        check_gl("stroke twin composite");
    }
    gl::Disable(GL_BLEND);
    gl::Disable(GL_DEPTH_TEST);
    gl::BindVertexArray(0);
    gl::DeleteVertexArrays(1, &vao);
    gl::DeleteVertexArrays(1, &empty_vao);
    gl::BindFramebuffer(GL_FRAMEBUFFER, 0);
    gl::DeleteFramebuffers(2, fbo);
    gl::DeleteRenderbuffers(1, &depth_rb);
    gl::BindSampler(1, 0);
    gl::DeleteSamplers(1, &smp);
    const ImageF rgba = read_texture(acc);
    ImageF out(W, H, 1);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) out.at(x, y, 0) = rgba.at(x, y, 0);
    return out;
}

}  // namespace aq::ref
