// scenes/procedural.cpp — procedural meshes and the "swatches" control test scene.
#include "scenes/procedural.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include "core/hash.h"
#include "scenes/noise.h"

namespace aq::scene {
namespace {

constexpr float kPi = 3.14159265358979323846f;
constexpr int kMaxSegments = 4096;

void check_range(const char* what, int v, int lo, int hi) {
    if (v < lo || v > hi)
        throw Error(std::string(what) + " = " + std::to_string(v) + " outside [" + std::to_string(lo) + ", " +
                    std::to_string(hi) + "]");
}

void add_quad(Primitive& p, std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
    // a-b-c-d counter-clockwise
    p.indices.insert(p.indices.end(), {a, b, c, a, c, d});
}

}  // namespace

Primitive make_grid(int n, float size) {
    check_range("make_grid n", n, 1, kMaxSegments);
    Primitive p;
    const int m = n + 1;
    p.positions.reserve(std::size_t(m) * m);
    for (int j = 0; j < m; ++j)
        for (int i = 0; i < m; ++i) {
            const float u = float(i) / float(n), v = float(j) / float(n);
            p.positions.push_back({(u - 0.5f) * size, (v - 0.5f) * size, 0.0f});
            p.normals.push_back({0.0f, 0.0f, 1.0f});
            p.uv0.push_back({u, v});
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const std::uint32_t a = std::uint32_t(j * m + i);
            add_quad(p, a, a + 1, a + 1 + std::uint32_t(m), a + std::uint32_t(m));
        }
    return p;
}

Primitive make_uv_sphere(int slices, int stacks, float radius) {
    check_range("make_uv_sphere slices", slices, 3, kMaxSegments);
    check_range("make_uv_sphere stacks", stacks, 2, kMaxSegments);
    Primitive p;
    // Vertex 0: north pole; then rings 1..stacks-1 with slices+1 vertices; last: south pole.
    p.positions.push_back({0.0f, radius, 0.0f});
    p.normals.push_back({0.0f, 1.0f, 0.0f});
    p.uv0.push_back({0.5f, 0.0f});
    const int row = slices + 1;
    for (int s = 1; s < stacks; ++s) {
        const float th = kPi * float(s) / float(stacks);
        for (int i = 0; i <= slices; ++i) {
            const int ii = i == slices ? 0 : i;  // seam: exact copy of column 0
            const float ph = 2.0f * kPi * float(ii) / float(slices);
            const glm::vec3 n(std::sin(th) * std::cos(ph), std::cos(th), -std::sin(th) * std::sin(ph));
            p.positions.push_back(n * radius);
            p.normals.push_back(n);
            p.uv0.push_back({float(i) / float(slices), float(s) / float(stacks)});
        }
    }
    const std::uint32_t south = std::uint32_t(p.positions.size());
    p.positions.push_back({0.0f, -radius, 0.0f});
    p.normals.push_back({0.0f, -1.0f, 0.0f});
    p.uv0.push_back({0.5f, 1.0f});
    auto ring = [&](int s, int i) { return std::uint32_t(1 + (s - 1) * row + i); };
    for (int i = 0; i < slices; ++i) p.indices.insert(p.indices.end(), {0u, ring(1, i), ring(1, i + 1)});
    for (int s = 1; s + 1 < stacks; ++s)
        for (int i = 0; i < slices; ++i) add_quad(p, ring(s, i), ring(s + 1, i), ring(s + 1, i + 1), ring(s, i + 1));
    for (int i = 0; i < slices; ++i) p.indices.insert(p.indices.end(), {ring(stacks - 1, i), south, ring(stacks - 1, i + 1)});
    return p;
}

Primitive make_fan(int segments, float radius) {
    check_range("make_fan segments", segments, 3, 1 << 20);
    Primitive p;
    p.positions.push_back({0.0f, 0.0f, 0.0f});
    p.normals.push_back({0.0f, 0.0f, 1.0f});
    p.uv0.push_back({0.5f, 0.5f});
    for (int i = 0; i < segments; ++i) {
        const float a = 2.0f * kPi * float(i) / float(segments);
        const glm::vec2 d(std::cos(a), std::sin(a));
        p.positions.push_back({d.x * radius, d.y * radius, 0.0f});
        p.normals.push_back({0.0f, 0.0f, 1.0f});
        p.uv0.push_back(0.5f + 0.5f * d);
    }
    for (int i = 0; i < segments; ++i) {
        const std::uint32_t a = std::uint32_t(1 + i), b = std::uint32_t(1 + (i + 1) % segments);
        p.indices.insert(p.indices.end(), {0u, a, b});
    }
    return p;
}

Primitive make_box(const glm::vec3& h) {
    Primitive p;
    const glm::vec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int a = 0; a < 3; ++a)
        for (int sgn = -1; sgn <= 1; sgn += 2) {
            const glm::vec3 n = axes[a] * float(sgn);
            const glm::vec3 u = axes[(a + 1) % 3] * float(sgn), v = axes[(a + 2) % 3];
            // u x v = n, so (c - u - v, c + u - v, c + u + v, c - u + v) is counter-clockwise.
            const glm::vec3 c = n * h;
            const glm::vec3 du = u * h, dv = v * h;
            const std::uint32_t base = std::uint32_t(p.positions.size());
            const glm::vec3 corners[4] = {c - du - dv, c + du - dv, c + du + dv, c - du + dv};
            const glm::vec2 uvs[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
            for (int k = 0; k < 4; ++k) {
                p.positions.push_back(corners[k]);
                p.normals.push_back(n);
                p.uv0.push_back(uvs[k]);
            }
            add_quad(p, base, base + 1, base + 2, base + 3);
        }
    return p;
}

Primitive make_torus(float R, float r, int nu, int nv) {
    check_range("make_torus major_segments", nu, 3, kMaxSegments);
    check_range("make_torus minor_segments", nv, 3, kMaxSegments);
    Primitive p;
    for (int i = 0; i <= nu; ++i) {
        const int ii = i == nu ? 0 : i;
        const float u = 2.0f * kPi * float(ii) / float(nu);
        for (int j = 0; j <= nv; ++j) {
            const int jj = j == nv ? 0 : j;
            const float v = 2.0f * kPi * float(jj) / float(nv);
            const glm::vec3 radial(std::cos(u), 0.0f, -std::sin(u));
            const glm::vec3 n = radial * std::cos(v) + glm::vec3(0, 1, 0) * std::sin(v);
            p.positions.push_back(radial * R + n * r);
            p.normals.push_back(n);
            p.uv0.push_back({float(i) / float(nu), float(j) / float(nv)});
        }
    }
    const std::uint32_t row = std::uint32_t(nv + 1);
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
            const std::uint32_t a = std::uint32_t(i) * row + std::uint32_t(j);
            add_quad(p, a, a + row, a + row + 1, a + 1);
        }
    return p;
}

Primitive make_cylinder(float radius, float height, int segments) {
    check_range("make_cylinder segments", segments, 3, kMaxSegments);
    Primitive p;
    const float hh = 0.5f * height;
    for (int i = 0; i <= segments; ++i) {
        const int ii = i == segments ? 0 : i;
        const float a = 2.0f * kPi * float(ii) / float(segments);
        const glm::vec3 n(std::cos(a), 0.0f, -std::sin(a));
        for (int k = 0; k < 2; ++k) {
            p.positions.push_back(n * radius + glm::vec3(0.0f, k ? hh : -hh, 0.0f));
            p.normals.push_back(n);
            p.uv0.push_back({float(i) / float(segments), float(k)});
        }
    }
    for (int i = 0; i < segments; ++i) {
        const std::uint32_t a = std::uint32_t(2 * i);
        add_quad(p, a, a + 2, a + 3, a + 1);
    }
    for (int k = 0; k < 2; ++k) {
        const float y = k ? hh : -hh;
        const glm::vec3 n(0.0f, k ? 1.0f : -1.0f, 0.0f);
        const std::uint32_t c = std::uint32_t(p.positions.size());
        p.positions.push_back({0.0f, y, 0.0f});
        p.normals.push_back(n);
        p.uv0.push_back({0.5f, 0.5f});
        for (int i = 0; i < segments; ++i) {
            const float a = 2.0f * kPi * float(i) / float(segments);
            p.positions.push_back({radius * std::cos(a), y, -radius * std::sin(a)});
            p.normals.push_back(n);
            p.uv0.push_back({0.5f + 0.5f * std::cos(a), 0.5f + 0.5f * std::sin(a)});
        }
        for (int i = 0; i < segments; ++i) {
            const std::uint32_t a = c + 1 + std::uint32_t(i), b = c + 1 + std::uint32_t((i + 1) % segments);
            if (k) p.indices.insert(p.indices.end(), {c, a, b});   // top, seen from +Y: counter-clockwise
            else p.indices.insert(p.indices.end(), {c, b, a});
        }
    }
    return p;
}

namespace {
Light default_key_light() {
    Light l;
    l.direction = glm::normalize(glm::vec3(-0.4f, 0.75f, 0.55f));
    return l;
}
}  // namespace

Scene make_single_mesh_scene(Primitive prim, const Material& material) {
    Scene s;
    prim.material = 0;
    s.materials.push_back(material);
    Mesh m;
    m.name = "mesh";
    m.primitives.push_back(std::move(prim));
    s.meshes.push_back(std::move(m));
    Instance inst;
    inst.name = "mesh";
    s.instances.push_back(inst);
    s.lights.push_back(default_key_light());
    s.source = "procedural";
    return s;
}

std::vector<std::string> procedural_names() { return {"swatches", "tree"}; }

namespace {

// Colours from the papers: WC17 Fig. 7 orange (194, 94, 0) and Fig. 10 blue (31, 171, 224), as
// display values (linear_color = false), with MNPR's reflectance values (the published ones).
Material swatch_material(const std::string& name, glm::vec3 rgb255) {
    Material m;
    m.name = name;
    m.wc = mnpr_watercolor_material();
    m.base_color = glm::vec4(rgb255 / 255.0f, 1.0f);
    return m;
}

void init_control(Primitive& p) {
    for (auto& c : p.control) c.assign(p.positions.size(), glm::vec4(0.0f));
}

// Smooth patch mask: 1 inside the noise blobs above `threshold`, fading over `soft`.
float patch(const glm::vec3& q, float freq, std::uint32_t seed, float threshold, float soft = 0.08f) {
    NoiseField f;
    f.frequency = freq;
    f.seed = seed;
    f.octaves = 2;
    const float n = noise_field(f, q);
    return std::clamp((n - threshold) / soft, 0.0f, 1.0f);
}

void add_instance(Scene& s, Primitive prim, int material, const glm::mat4& world, const std::string& name) {
    prim.material = material;
    Mesh m;
    m.name = name;
    m.primitives.push_back(std::move(prim));
    s.meshes.push_back(std::move(m));
    Instance inst;
    inst.mesh = int(s.meshes.size()) - 1;
    inst.world = world;
    inst.object_id = std::uint32_t(s.instances.size() + 1);
    inst.name = name;
    s.instances.push_back(inst);
}

Scene make_swatches() {
    Scene s;
    s.source = "procedural:swatches";
    s.materials = {swatch_material("ground", {190, 160, 110}), swatch_material("orange", {194, 94, 0}),
                   swatch_material("blue", {31, 171, 224}),    swatch_material("red", {200, 40, 50}),
                   swatch_material("green", {60, 150, 70}),    swatch_material("violet", {120, 70, 170})};
    s.materials[1].wc.specular = 0.3f;  // shows the specular term on one sphere
    s.materials[0].wc.dilute = 0.25f;   // the lit ground would otherwise dilute to the paper colour

    // Ground plane (XZ, 8 x 6 units): granulation (+) to dry-brush (-) gradient along X, a
    // paper-distortion band along Z and pigment-variation noise.
    {
        Primitive g = make_grid(64, 1.0f);
        for (std::size_t i = 0; i < g.positions.size(); ++i) {  // XY unit grid -> XZ 8 x 6
            const glm::vec3 q = g.positions[i];
            g.positions[i] = {q.x * 8.0f, 0.0f, -q.y * 6.0f};
            g.normals[i] = {0.0f, 1.0f, 0.0f};
        }
        init_control(g);
        for (std::size_t i = 0; i < g.positions.size(); ++i) {
            const glm::vec3 q = g.positions[i];
            const float gx = std::clamp(q.x / 4.0f, -1.0f, 1.0f);
            g.control[kCtrlPigment][i].g = gx;                                      // application
            g.control[kCtrlPigment][i].r = std::clamp(noise_field({1.5f, 1.8f, 0.0f, 11u, 2}, q), -1.0f, 1.0f);  // variation
            g.control[kCtrlSubstrate][i].r = std::abs(q.z - 1.5f) < 0.6f ? 1.0f : 0.0f;  // distortion band
        }
        add_instance(s, std::move(g), 0, glm::mat4(1.0f), "ground");
    }
    // Sphere A (orange): edge intensity gradient bottom (-1) to top (+1), edge width band.
    {
        Primitive p = make_uv_sphere(64, 32, 1.0f);
        init_control(p);
        for (std::size_t i = 0; i < p.positions.size(); ++i) {
            const glm::vec3 q = p.positions[i];
            p.control[kCtrlEdge][i].r = q.y;
            p.control[kCtrlEdge][i].g = q.x > 0.3f ? 1.0f : 0.0f;
        }
        add_instance(s, std::move(p), 1, glm::translate(glm::mat4(1.0f), {-2.4f, 1.0f, 0.2f}), "sphere_edges");
    }
    // Sphere B (blue): bleeding patches and a density (turbulence) noise field.
    {
        Primitive p = make_uv_sphere(64, 32, 1.0f);
        init_control(p);
        for (std::size_t i = 0; i < p.positions.size(); ++i) {
            const glm::vec3 q = p.positions[i];
            p.control[kCtrlAbstraction][i].b = patch(q, 1.6f, 21u, 0.1f);
            p.control[kCtrlPigment][i].b = std::clamp(noise_field({2.5f, 1.8f, 0.0f, 22u, 3}, q), -1.0f, 1.0f);
        }
        add_instance(s, std::move(p), 2, glm::translate(glm::mat4(1.0f), {0.0f, 1.0f, -0.6f}), "sphere_bleed");
    }
    // Box (red): gaps on the left half (-), overlaps on the right half (+), strong edges.
    {
        Primitive p = make_box(glm::vec3(0.7f));
        init_control(p);
        for (std::size_t i = 0; i < p.positions.size(); ++i) {
            const glm::vec3 q = p.positions[i];
            p.control[kCtrlEdge][i].b = q.x < 0.0f ? -1.0f : 1.0f;
            p.control[kCtrlEdge][i].r = 0.6f;
        }
        const glm::mat4 w = glm::rotate(glm::translate(glm::mat4(1.0f), {2.5f, 0.7f, 0.4f}), 0.6f, glm::vec3(0, 1, 0));
        add_instance(s, std::move(p), 3, w, "box_gaps_overlaps");
    }
    // Torus (green): granulation patches and dry-brush patches.
    {
        Primitive p = make_torus(0.8f, 0.3f, 64, 24);
        init_control(p);
        for (std::size_t i = 0; i < p.positions.size(); ++i) {
            const glm::vec3 q = p.positions[i];
            p.control[kCtrlPigment][i].g = patch(q, 2.0f, 31u, 0.15f) - patch(q, 2.0f, 32u, 0.25f);
        }
        const glm::mat4 w = glm::rotate(glm::translate(glm::mat4(1.0f), {-0.4f, 0.35f, 2.0f}), 0.35f, glm::vec3(1, 0, 0));
        add_instance(s, std::move(p), 4, w, "torus_granulation");
    }
    // Cylinder (violet): distortion band around the middle, abstraction detail/shape gradient,
    // dilution (negative density) towards the top.
    {
        Primitive p = make_cylinder(0.5f, 2.0f, 48);
        init_control(p);
        for (std::size_t i = 0; i < p.positions.size(); ++i) {
            const glm::vec3 q = p.positions[i];
            p.control[kCtrlSubstrate][i].r = std::abs(q.y) < 0.3f ? 1.0f : 0.0f;
            p.control[kCtrlAbstraction][i].r = q.y;
            p.control[kCtrlAbstraction][i].g = -q.y;
            p.control[kCtrlPigment][i].b = -std::clamp(q.y, 0.0f, 1.0f);
        }
        add_instance(s, std::move(p), 5, glm::translate(glm::mat4(1.0f), {1.6f, 1.0f, 2.2f}), "cylinder_distortion");
    }

    s.lights.push_back(default_key_light());
    Light fill;
    fill.direction = glm::normalize(glm::vec3(0.6f, 0.3f, -0.4f));
    fill.intensity = 0.3f;
    s.lights.push_back(fill);
    s.ambient = glm::vec3(0.05f);

    Camera cam;
    cam.name = "swatches";
    cam.view = glm::lookAt(glm::vec3(0.0f, 5.0f, 9.0f), glm::vec3(0.0f, 0.6f, 0.6f), glm::vec3(0, 1, 0));
    cam.yfov = 0.75f;
    cam.znear = 0.5f;
    cam.zfar = 40.0f;
    s.cameras.push_back(cam);
    return s;
}

// ---- "tree": a family of procedural plants for LD06 (docs/ld06.md "Procedural plants") ----------

// Recursive branching, every choice keyed by the branch index (and the seed) through hash32 (same
// plant every run). Kind "broadleaf" with the default proportions and seed 0 is the original
// `procedural:tree`, byte for byte.
constexpr float kTreeTrunkLength = 9.0f, kTreeTrunkRadius = 0.55f;
constexpr int kTreeDepth = 4, kTreeChildren = 3, kTreeLeavesPerBranch = 10, kTreeTubeSides = 8;
constexpr float kTreeLengthRatio = 0.68f, kTreeRadiusRatio = 0.55f, kTreeLeafSize = 0.9f;

//! The parameters of one generated plant (`procedural:tree?kind=K&seed=S&...`).
struct PlantSpec {
    std::string kind = "broadleaf";
    std::uint32_t seed = 0;
    float height = 1.0f;   //!< scale of the whole plant
    float leaves = 1.0f;   //!< leaves per branch, relative to the kind's default
    float leaf_size = 1.0f;  //!< relative to the kind's default
    float spread = 1.0f;   //!< branch angle (crown width), relative to the kind's default
};

float tree_rand(std::uint32_t id, std::uint32_t k, std::uint32_t seed = 0) {
    return float(hash32((id + seed * 0x85EBCA6Bu) * 0x9E3779B1u + k) >> 8) / 16777216.0f;
}

glm::vec3 any_perpendicular(glm::vec3 d) {
    const glm::vec3 a = std::abs(d.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
    return glm::normalize(glm::cross(d, a));
}

// An open tapered tube from a (radius ra) to b (radius rb), normals radial.
void add_tube(Primitive& p, glm::vec3 a, glm::vec3 b, float ra, float rb) {
    const glm::vec3 d = glm::normalize(b - a);
    const glm::vec3 u = any_perpendicular(d), v = glm::cross(d, u);
    const std::uint32_t base = std::uint32_t(p.positions.size());
    for (int i = 0; i <= kTreeTubeSides; ++i) {
        const float ang = 2.0f * kPi * float(i % kTreeTubeSides) / float(kTreeTubeSides);
        const glm::vec3 n = u * std::cos(ang) + v * std::sin(ang);
        p.positions.push_back(a + n * ra);
        p.normals.push_back(n);
        p.uv0.push_back({float(i) / float(kTreeTubeSides), 0.0f});
        p.positions.push_back(b + n * rb);
        p.normals.push_back(n);
        p.uv0.push_back({float(i) / float(kTreeTubeSides), 1.0f});
    }
    for (int i = 0; i < kTreeTubeSides; ++i) {
        const std::uint32_t k = base + std::uint32_t(2 * i);
        add_quad(p, k, k + 2, k + 3, k + 1);
    }
}

// Two crossed quads centred at c (like the shared ez-tree leaves), facing directions from the seed.
void add_leaf(Primitive& p, glm::vec3 c, std::uint32_t id, float size = kTreeLeafSize, std::uint32_t seed = 0) {
    const glm::vec3 n = glm::normalize(
        glm::vec3(tree_rand(id, 1, seed) - 0.5f, tree_rand(id, 2, seed) * 0.8f + 0.2f, tree_rand(id, 3, seed) - 0.5f));
    const glm::vec3 u = any_perpendicular(n), w = glm::cross(n, u);
    const float h = 0.5f * size;
    for (const auto& [a, b] : {std::pair{u, w}, std::pair{u, n}}) {
        const glm::vec3 nn = glm::normalize(glm::cross(a, b));
        const std::uint32_t k = std::uint32_t(p.positions.size());
        for (const glm::vec2 q : {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(1, 1), glm::vec2(-1, 1)}) {
            p.positions.push_back(c + (a * q.x + b * q.y) * h);
            p.normals.push_back(nn);
            p.uv0.push_back((q + 1.0f) * 0.5f);
        }
        add_quad(p, k, k + 1, k + 2, k + 3);
    }
}

// A grass blade: a bent strip of `segs` quads from `base` along `dir`, narrowing to the tip.
void add_blade(Primitive& p, glm::vec3 base, glm::vec3 dir, glm::vec3 side, float length, float width, float bend) {
    constexpr int segs = 4;
    const std::uint32_t k0 = std::uint32_t(p.positions.size());
    glm::vec3 c = base, d = dir;
    for (int i = 0; i <= segs; ++i) {
        const float t = float(i) / float(segs), hw = 0.5f * width * (1.0f - 0.85f * t);
        const glm::vec3 n = glm::normalize(glm::cross(side, d));
        for (float s : {-1.0f, 1.0f}) {
            p.positions.push_back(c + side * (s * hw));
            p.normals.push_back(n);
            p.uv0.push_back({0.5f + 0.5f * s, t});
        }
        c += d * (length / float(segs));
        d = glm::normalize(d + glm::vec3(0, -bend, 0) + glm::cross(side, glm::vec3(0, 1, 0)) * (0.5f * bend));
    }
    for (int i = 0; i < segs; ++i) {
        const std::uint32_t k = k0 + std::uint32_t(2 * i);
        add_quad(p, k, k + 1, k + 3, k + 2);
    }
}

struct TreeBranch {
    glm::vec3 base, dir;
    float length, radius;
    int depth;
    std::uint32_t id;
};

//! How a branching kind grows (broadleaf, light, shrub).
struct BranchingRule {
    std::vector<TreeBranch> roots;
    int depth = kTreeDepth, children = kTreeChildren, leaves_per_branch = kTreeLeavesPerBranch;
    int leafy_from = kTreeDepth - 1;  //!< branches of this depth and deeper carry leaves
    float tilt0 = 0.45f, tilt1 = 0.35f, up = 0.25f, jitter = 1.2f, leaf_size = kTreeLeafSize;
};

void grow(const BranchingRule& rule, const PlantSpec& sp, Primitive& bark, Primitive& leaves) {
    std::vector<TreeBranch> todo = rule.roots;
    std::uint32_t next_id = 2;
    for (const TreeBranch& r : rule.roots) next_id = std::max(next_id, r.id + 1);
    const std::uint32_t seed = sp.seed;
    for (std::size_t i = 0; i < todo.size(); ++i) {  // breadth first: a fixed order
        const TreeBranch br = todo[i];
        const glm::vec3 tip = br.base + br.dir * br.length;
        add_tube(bark, br.base, tip, br.radius, br.radius * kTreeRadiusRatio);
        if (br.depth >= rule.leafy_from)
            for (int k = 0; k < rule.leaves_per_branch; ++k) {
                const std::uint32_t lid = br.id * 64u + std::uint32_t(k);
                const glm::vec3 jitter =
                    glm::vec3(tree_rand(lid, 4, seed), tree_rand(lid, 5, seed), tree_rand(lid, 6, seed)) - 0.5f;
                add_leaf(leaves, br.base + br.dir * (br.length * (0.3f + 0.7f * tree_rand(lid, 7, seed))) + jitter * rule.jitter * sp.height,
                         lid, rule.leaf_size, seed);
            }
        if (br.depth == rule.depth) continue;
        const glm::vec3 u = any_perpendicular(br.dir), v = glm::cross(br.dir, u);
        for (int c = 0; c < rule.children; ++c) {
            const float az = 2.0f * kPi * (float(c) + 0.4f * tree_rand(br.id, 10u + std::uint32_t(c), seed)) / float(rule.children);
            const float tilt = sp.spread * (rule.tilt0 + rule.tilt1 * tree_rand(br.id, 20u + std::uint32_t(c), seed));
            const glm::vec3 side = u * std::cos(az) + v * std::sin(az);
            glm::vec3 dir = glm::normalize(br.dir * std::cos(tilt) + side * std::sin(tilt));
            dir = glm::normalize(dir + glm::vec3(0, rule.up, 0));  // branches reach up
            const float at = 0.55f + 0.4f * tree_rand(br.id, 30u + std::uint32_t(c), seed);
            todo.push_back({br.base + br.dir * (br.length * at), dir, br.length * kTreeLengthRatio,
                            br.radius * kTreeRadiusRatio * (1.2f - 0.4f * at), br.depth + 1, next_id++});
        }
    }
}

int scaled_count(int n, float f) { return std::max(1, int(std::lround(float(n) * f))); }

// A conifer: one straight stem, whorls of drooping branches shortening towards the top (a cone),
// needle tufts (small crossed quads) along every branch.
void grow_conifer(const PlantSpec& sp, Primitive& bark, Primitive& leaves) {
    const float H = 22.0f * sp.height, base_r = 0.45f * sp.height;
    add_tube(bark, {0, 0, 0}, {0, H, 0}, base_r, base_r * 0.15f);
    const int whorls = 14, per = 6;
    const float needle = 0.7f * sp.leaf_size * sp.height;
    for (int w = 0; w < whorls; ++w) {
        const float t = 0.18f + 0.8f * float(w) / float(whorls - 1);  // height fraction
        const float len = (1.0f - t) * 0.42f * H * sp.spread + 0.6f * sp.height;
        for (int b = 0; b < per; ++b) {
            const std::uint32_t id = std::uint32_t(w * per + b + 1);
            const float az = 2.0f * kPi * (float(b) + 0.5f * float(w % 2) + 0.3f * tree_rand(id, 1, sp.seed)) / float(per);
            const float droop = -0.25f - 0.2f * tree_rand(id, 2, sp.seed);
            const glm::vec3 dir = glm::normalize(glm::vec3(std::cos(az), droop, std::sin(az)));
            const glm::vec3 a = {0, t * H, 0};
            add_tube(bark, a, a + dir * len, base_r * 0.25f * (1.0f - t) + 0.03f, 0.02f);
            const int tufts = scaled_count(int(len / (0.35f * sp.height)) + 2, sp.leaves);
            for (int k = 0; k < tufts; ++k) {
                const std::uint32_t lid = id * 256u + std::uint32_t(k);
                const float along = (float(k) + 0.5f) / float(tufts);
                const glm::vec3 j = glm::vec3(tree_rand(lid, 4, sp.seed), tree_rand(lid, 5, sp.seed), tree_rand(lid, 6, sp.seed)) - 0.5f;
                add_leaf(leaves, a + dir * (len * along) + j * (0.5f * sp.height), lid, needle * (1.2f - 0.5f * along), sp.seed);
            }
        }
    }
}

// Grass-like small plant: a tuft of blades from one point, foliage only (no bark).
void grow_grass(const PlantSpec& sp, Primitive& leaves) {
    const int blades = scaled_count(40, sp.leaves);
    for (int i = 0; i < blades; ++i) {
        const std::uint32_t id = std::uint32_t(i + 1);
        const float az = 2.0f * kPi * tree_rand(id, 1, sp.seed);
        const float lean = sp.spread * (0.15f + 0.45f * tree_rand(id, 2, sp.seed));
        const glm::vec3 out = {std::cos(az), 0, std::sin(az)};
        const glm::vec3 dir = glm::normalize(glm::vec3(0, 1, 0) + out * lean);
        const glm::vec3 side = glm::normalize(glm::cross(dir, out));
        const glm::vec3 base = out * (0.3f * tree_rand(id, 3, sp.seed) * sp.height);
        add_blade(leaves, base, dir, side, (3.0f + 3.0f * tree_rand(id, 4, sp.seed)) * sp.height,
                  0.22f * sp.leaf_size * sp.height, 0.12f * sp.spread);
    }
}

PlantSpec parse_plant_spec(const std::string& query) {
    PlantSpec sp;
    std::size_t at = 0;
    while (at < query.size()) {
        std::size_t amp = query.find('&', at);
        if (amp == std::string::npos) amp = query.size();
        const std::string kv = query.substr(at, amp - at);
        at = amp + 1;
        const std::size_t eq = kv.find('=');
        if (eq == std::string::npos) throw Error("procedural:tree: '" + kv + "' is not KEY=VALUE (docs/ld06.md \"Procedural plants\")");
        const std::string k = kv.substr(0, eq), v = kv.substr(eq + 1);
        if (k == "kind") {
            if (v != "broadleaf" && v != "light" && v != "conifer" && v != "shrub" && v != "grass")
                throw Error("procedural:tree: unknown kind '" + v + "' (known: broadleaf, light, conifer, shrub, grass)");
            sp.kind = v;
            continue;
        }
        char* end = nullptr;
        const double x = std::strtod(v.c_str(), &end);
        if (v.empty() || *end != '\0' || !std::isfinite(x)) throw Error("procedural:tree: " + k + " = '" + v + "' is not a number");
        auto ranged = [&](float& dst, double lo, double hi) {
            if (x < lo || x > hi)
                throw Error("procedural:tree: " + k + " = " + v + " outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
            dst = float(x);
        };
        if (k == "seed") {
            if (x < 0 || x > 4294967295.0 || x != std::floor(x)) throw Error("procedural:tree: seed must be an integer in [0, 2^32)");
            sp.seed = std::uint32_t(x);
        } else if (k == "height") ranged(sp.height, 0.01, 100.0);
        else if (k == "leaves") ranged(sp.leaves, 0.05, 4.0);
        else if (k == "leaf_size") ranged(sp.leaf_size, 0.1, 4.0);
        else if (k == "spread") ranged(sp.spread, 0.2, 2.0);
        else throw Error("procedural:tree: unknown parameter '" + k + "' (known: kind, seed, height, leaves, leaf_size, spread)");
    }
    return sp;
}

Scene make_tree(const PlantSpec& sp) {
    Primitive bark, leaves;
    const float s = sp.height;
    if (sp.kind == "broadleaf" || sp.kind == "light") {
        BranchingRule r;
        r.roots = {{{0, 0, 0}, {0, 1, 0}, kTreeTrunkLength * s, kTreeTrunkRadius * s, 0, 1}};
        r.leaves_per_branch = scaled_count(sp.kind == "light" ? 4 : kTreeLeavesPerBranch, sp.leaves);
        if (sp.kind == "light") r.leafy_from = kTreeDepth, r.tilt0 = 0.6f;  // leaves on the last twigs only
        r.leaf_size = kTreeLeafSize * sp.leaf_size * s;
        r.jitter = sp.kind == "light" ? 2.0f : 1.2f;
        grow(r, sp, bark, leaves);
    } else if (sp.kind == "shrub") {
        BranchingRule r;
        const int stems = 5 + int(tree_rand(0, 1, sp.seed) * 3.0f);
        for (int i = 0; i < stems; ++i) {
            const float az = 2.0f * kPi * (float(i) + 0.5f * tree_rand(std::uint32_t(i), 2, sp.seed)) / float(stems);
            const glm::vec3 d = glm::normalize(glm::vec3(0.45f * std::cos(az), 1.0f, 0.45f * std::sin(az)));
            r.roots.push_back({{0, 0, 0}, d, 3.2f * s, 0.12f * s, 1, std::uint32_t(i + 1)});
        }
        r.depth = 3, r.children = 2, r.leafy_from = 3;
        r.leaves_per_branch = scaled_count(3, sp.leaves);
        r.leaf_size = 0.55f * sp.leaf_size * s, r.jitter = 0.5f, r.up = 0.4f;
        grow(r, sp, bark, leaves);
    } else if (sp.kind == "conifer") {
        grow_conifer(sp, bark, leaves);
    } else {
        grow_grass(sp, leaves);
    }
    Scene sc;
    Material bark_m;
    bark_m.name = "bark";
    bark_m.base_color = {0.38f, 0.27f, 0.18f, 1.0f};
    Material leaf_m;
    leaf_m.name = "leaves";
    leaf_m.base_color = sp.kind == "conifer" ? glm::vec4(0.16f, 0.36f, 0.22f, 1.0f)
                        : sp.kind == "grass" ? glm::vec4(0.45f, 0.6f, 0.2f, 1.0f)
                                             : glm::vec4(0.32f, 0.55f, 0.22f, 1.0f);
    leaf_m.double_sided = true;
    sc.materials = {bark_m, leaf_m};
    bark.material = 0;
    leaves.material = 1;
    for (auto [prim, name] : {std::pair{&bark, "trunk"}, std::pair{&leaves, "foliage"}}) {
        if (prim->indices.empty()) continue;  // grass: foliage only
        Mesh m;
        m.name = name;
        m.primitives.push_back(std::move(*prim));
        sc.meshes.push_back(std::move(m));
        Instance inst;
        inst.mesh = int(sc.meshes.size()) - 1;
        inst.object_id = std::uint32_t(sc.meshes.size());
        inst.name = name;
        sc.instances.push_back(inst);
    }
    sc.lights.push_back(default_key_light());
    sc.ambient = glm::vec3(0.05f);
    const Bounds b = sc.world_bounds();
    const glm::vec3 c = 0.5f * (b.min + b.max);
    const float r = 0.5f * glm::length(b.max - b.min);
    Camera cam;
    cam.name = "tree";
    cam.yfov = 0.7f;
    const float d = r / std::sin(0.35f) * 1.05f;
    cam.view = glm::lookAt(c + glm::normalize(glm::vec3(0.3f, 0.15f, 1.0f)) * d, c, glm::vec3(0, 1, 0));
    cam.znear = d - 1.1f * r;
    cam.zfar = d + 1.1f * r;
    sc.cameras.push_back(cam);
    sc.source = "procedural:tree";
    return sc;
}

}  // namespace

Scene make_procedural(const std::string& name) {
    if (name == "swatches") return make_swatches();
    if (name == "tree") return make_tree(PlantSpec{});
    if (name.rfind("tree?", 0) == 0) {
        Scene s = make_tree(parse_plant_spec(name.substr(5)));
        s.source = "procedural:" + name;
        return s;
    }
    std::string known;
    for (const std::string& n : procedural_names()) known += (known.empty() ? "" : ", ") + n;
    throw Error("unknown procedural scene '" + name + "' (known: " + known + ")");
}

}  // namespace aq::scene
