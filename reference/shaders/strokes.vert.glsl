// strokes.vert.glsl — vertex stage of the LD06 stroke twin (raster/strokes.h): one quad per
// segment covering its capsule (the segment's pixel bounding box grown by half the width + 1),
// the segment's view-space ends and normals passed flat to the fragment stage, which decides
// coverage (distance to the projected segment) and the stroke's alpha.
#version 450 core
layout(location = 0) in vec3 a_pa;
layout(location = 1) in vec3 a_pb;
layout(location = 2) in vec3 a_na;
layout(location = 3) in vec3 a_nb;
layout(location = 4) in vec2 a_corner;   // (0|1, 0|1)
layout(location = 5) in float a_has_normal;

uniform mat4 u_projection;
uniform vec2 u_size;   // raster size in pixels
uniform float u_half;  // half the line width in pixels

flat out vec3 v_pa, v_pb, v_na, v_nb;
flat out vec4 v_seg;  // projected ends (x0, y0, x1, y1), pixels, y down
flat out float v_has_normal;

vec2 to_pixels(vec3 v) {
    vec4 c = u_projection * vec4(v, 1.0);
    return vec2((c.x / c.w + 1.0) * 0.5 * u_size.x, (1.0 - c.y / c.w) * 0.5 * u_size.y);
}

void main() {
    vec2 p0 = to_pixels(a_pa), p1 = to_pixels(a_pb);
    v_pa = a_pa;
    v_pb = a_pb;
    v_na = a_na;
    v_nb = a_nb;
    v_seg = vec4(p0, p1);
    v_has_normal = a_has_normal;
    vec2 lo = min(p0, p1) - vec2(u_half + 1.0), hi = max(p0, p1) + vec2(u_half + 1.0);
    vec2 q = mix(lo, hi, a_corner);
    // pixel (x, y) with y down -> GL window row y: row 0 of the read-back image is the top row
    gl_Position = vec4(q / u_size * 2.0 - 1.0, 0.5, 1.0);
}
