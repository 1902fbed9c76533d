// pass.vert.glsl — vertex stage of the LD06 raster-pass twin (raster/pass.h): model-view-projection
// of the pass view, no tremor or displacement (LD06 has neither). As gbuffer.vert.glsl, clip y is
// negated last so GL row y is image row y.
#version 450 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_uv;
layout(location = 3) in vec4 a_color;

uniform mat4 u_model_view;
uniform mat3 u_normal_matrix;
uniform mat4 u_projection;

out vec3 v_view_pos;
out vec3 v_normal;
out vec2 v_uv;
out vec4 v_color;

void main() {
    vec4 v = u_model_view * vec4(a_position, 1.0);
    vec4 c = u_projection * v;
    float l2 = dot(u_normal_matrix * a_normal, u_normal_matrix * a_normal);
    v_normal = l2 > 0.0 ? (u_normal_matrix * a_normal) * (1.0 / sqrt(l2)) : u_normal_matrix * a_normal;
    v_view_pos = v.xyz;
    v_uv = a_uv;
    v_color = a_color;
    c.y = -c.y;
    gl_Position = c;
}
