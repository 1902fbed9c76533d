// particles.vert.glsl — vertex stage of the LD06 particle twin (raster/particles.h): the particle's
// projection, its normalised depth d and eq. 10's sprite size s = ((1 - d) * scale + bias) * W / 720
// as a GL point; the class (eq. 11, computed at placement) picks the output channel.
#version 450 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in float a_class;

uniform mat4 u_view;
uniform mat4 u_projection;
uniform float u_depth_near, u_depth_far;
uniform float u_size_scale, u_size_bias, u_width;

flat out float v_depth;
flat out int v_class;

void main() {
    vec4 v = u_view * vec4(a_position, 1.0);
    vec4 c = u_projection * v;
    v_depth = (-v.z - u_depth_near) / (u_depth_far - u_depth_near);
    v_class = int(a_class);
    gl_PointSize = ((1.0 - clamp(v_depth, 0.0, 1.0)) * u_size_scale + u_size_bias) * (u_width / 720.0);
    c.y = -c.y;
    gl_Position = c;
}
