// Shared body of the substrate_light twins.
void main() {
    vec4 c = fetch(s_color, pixel());
#if HAS_paper
    vec2 tex = fetch(s_paper, pixel()).rg;
#else
    vec2 tex = vec2(0.5);
#endif
    float rad = u_direction * 3.14159265 / 180.0;
    vec3 l = vec3(sin(rad), cos(rad), u_tilt / 89.0);
    vec3 n = vec3(-(tex - 0.5) * u_roughness, 1.0);
    float u = 1.0 - dot(n, l);
#if SQUARED
    float id = 1.0 - u * u * u_shading;
#else
    float id = 1.0 - u * u_shading;
#endif
    if (u_normalize) {  // divide by the flat paper's Id (N = (0, 0, 1)), as a multiplication by 1 / Id_flat
        float u0 = 1.0 - l.z;
#if SQUARED
        float flat_id = 1.0 - u0 * u0 * u_shading;
#else
        float flat_id = 1.0 - u0 * u_shading;
#endif
        float norm = flat_id > 0.0 ? 1.0 / flat_id : 1.0;
        id = id * norm;
    }
    o_color = vec4(c.rgb * id, c.a);
}
