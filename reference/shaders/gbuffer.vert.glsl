// gbuffer.vert.glsl — vertex stage of the G-buffer twin (spec §2): WC17 §3.2 bleeding displacement
// (MNPR: p += n * sat(ctrl_bleed - 0.7) * 0.5), model-view-projection, WC17 eq. 1-2 hand tremor in
// MNPR's form, in output pixels: off = sin(T * speed * 100 + p.xy * freq * 10) * tremor *
// min(sat(1.2 N.V), 1 - front), added to clip.xy as off * (2 / size) * w. The image is y-down,
// GL's window y-up: clip y is negated last so GL row y is image row y.
#version 450 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec4 a_tangent;
layout(location = 3) in vec2 a_uv;
layout(location = 4) in vec4 a_color;
layout(location = 5) in vec4 a_ctrl0;
layout(location = 6) in vec4 a_ctrl1;
layout(location = 7) in vec4 a_ctrl2;
layout(location = 8) in vec4 a_ctrl3;

uniform mat4 u_model_view;
uniform mat3 u_normal_matrix;
uniform mat4 u_projection;
uniform bool u_perspective;
uniform bool u_tremor;
uniform float u_tremor_px, u_front, u_speed, u_frequency, u_time;
uniform bool u_bleed_displacement;
uniform float u_bleed_const;          // material constant of ctrl.abstraction.b
uniform vec2 u_size;                  // output size in pixels

out vec3 v_view_pos;
out vec3 v_normal;
out vec4 v_tangent;
out vec2 v_uv;
out vec4 v_color;
out vec3 v_ctrl[4];
out float v_depth;

vec3 safe_normalize(vec3 v) { float l2 = dot(v, v); return l2 > 0.0 ? v * (1.0 / sqrt(l2)) : v; }

void main() {
    vec3 p = a_position;
    vec3 pd = p;
    if (u_bleed_displacement) {
        float cb = clamp(u_bleed_const + a_ctrl3.b, -1.0, 1.0);
        pd = p + a_normal * (clamp(cb - 0.7, 0.0, 1.0) * 0.5);
    }
    vec4 v = u_model_view * vec4(pd, 1.0);
    vec4 c = u_projection * v;
    vec3 nv = safe_normalize(u_normal_matrix * a_normal);
    if (u_tremor) {
        vec3 vdir = u_perspective ? safe_normalize(-v.xyz) : vec3(0.0, 0.0, 1.0);
        float w = min(clamp(1.2 * dot(nv, vdir), 0.0, 1.0), 1.0 - u_front);
        float phase = (u_time * u_speed) * 100.0;
        vec2 off = sin(phase + (p.xy * u_frequency) * 10.0) * u_tremor_px * w;
        c.xy += (off * (2.0 / u_size)) * c.w;
    }
    v_view_pos = v.xyz;
    v_normal = nv;
    v_tangent = vec4(safe_normalize(mat3(u_model_view) * a_tangent.xyz), a_tangent.w);
    v_uv = a_uv;
    v_color = a_color;
    v_ctrl[0] = a_ctrl0.rgb;
    v_ctrl[1] = a_ctrl1.rgb;
    v_ctrl[2] = a_ctrl2.rgb;
    v_ctrl[3] = a_ctrl3.rgb;
    v_depth = -v.z;
    gl_Position = vec4(c.x, -c.y, c.z, c.w);
}
