// raster/implicit_surface.cpp — LD06 eq. 6-7 summed on a grid, polygonised by surface nets.
#include "raster/implicit_surface.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace aq::raster {

namespace {

// Eq. 6 for a squared distance: (1 - d²/r²)² inside r, else 0.
inline float kernel(float d2, float inv_r2) {
    const float w = 1.0f - d2 * inv_r2;
    return w > 0.0f ? w * w : 0.0f;
}

struct Grid {
    glm::vec3 origin{0};
    float cell = 1;
    int nx = 0, ny = 0, nz = 0;
    std::size_t at(int i, int j, int k) const { return (std::size_t(k) * ny + j) * nx + i; }
    glm::vec3 node(int i, int j, int k) const { return origin + glm::vec3(float(i), float(j), float(k)) * cell; }
};

inline float lerp(float a, float b, float t) { return a + (b - a) * t; }

// The trilinear interpolation of the 8 corner values c (corner index: bit 0 = x, bit 1 = y,
// bit 2 = z) at local coordinates u, and its gradient.
float trilinear(const float c[8], glm::vec3 u) {
    return lerp(lerp(lerp(c[0], c[1], u.x), lerp(c[2], c[3], u.x), u.y), lerp(lerp(c[4], c[5], u.x), lerp(c[6], c[7], u.x), u.y),
                u.z);
}
glm::vec3 trilinear_gradient(const float c[8], glm::vec3 u) {
    const float gx = lerp(lerp(c[1] - c[0], c[3] - c[2], u.y), lerp(c[5] - c[4], c[7] - c[6], u.y), u.z);
    const float gy = lerp(lerp(c[2] - c[0], c[3] - c[1], u.x), lerp(c[6] - c[4], c[7] - c[5], u.x), u.z);
    const float gz = lerp(lerp(c[4] - c[0], c[5] - c[1], u.x), lerp(c[6] - c[2], c[7] - c[3], u.x), u.y);
    return {gx, gy, gz};
}

constexpr int kCorner[8][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}};
constexpr int kEdge[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3}, {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

}  // namespace

float implicit_density(const std::vector<glm::vec3>& points, float radius, glm::vec3 p) {
    const float inv_r2 = 1.0f / (radius * radius);
    float s = 0.0f;
    for (const glm::vec3& c : points) {
        const glm::vec3 d = p - c;
        s += kernel(d.x * d.x + d.y * d.y + d.z * d.z, inv_r2);
    }
    return s;
}

namespace {

void check_params(const ImplicitSurfaceParams& p) {
    if (!(std::isfinite(p.threshold) && p.threshold > 0.0f)) throw Error("implicit surface: T must be finite and > 0");
    if (!(p.fit_inside >= 0.0f && p.fit_inside < 1.0f)) throw Error("implicit surface: fit_inside must be in [0, 1)");
    if (!(std::isfinite(p.radius) && p.radius > 0.0f)) throw Error("implicit surface: r must be finite and > 0");
    if (p.cells_per_radius < 1 || p.cells_per_radius > 16)
        throw Error("implicit surface: cells_per_radius must be in [1, 16]");
}

//! The finite constraint points, in order, and their bounds.
struct Points {
    std::vector<glm::vec3> pts;
    glm::vec3 lo{std::numeric_limits<float>::infinity()}, hi{-std::numeric_limits<float>::infinity()};
};

Points finite_points(const std::vector<glm::vec3>& points_in) {
    Points r;
    r.pts.reserve(points_in.size());
    for (const glm::vec3& c : points_in)
        if (std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z)) {
            r.pts.push_back(c);
            r.lo = glm::min(r.lo, c);
            r.hi = glm::max(r.hi, c);
        }
    if (r.pts.empty()) throw Error("implicit surface: no finite constraint point");
    return r;
}

//! The field's grid around the points: one empty cell beyond every kernel's support on each side,
//! so the surface is closed. Its node count and the field's work are bounded before anything is
//! allocated (docs/limits.md "Work budgets").
Grid make_grid(const Points& pt, const ImplicitSurfaceParams& p) {
    Grid g;
    g.cell = p.radius / float(p.cells_per_radius);
    g.origin = pt.lo - glm::vec3(p.radius + g.cell);
    const glm::dvec3 extent = glm::dvec3(pt.hi - pt.lo) + 2.0 * double(p.radius + g.cell);
    const double n[3] = {std::ceil(extent.x / g.cell) + 1, std::ceil(extent.y / g.cell) + 1, std::ceil(extent.z / g.cell) + 1};
    const double nodes = n[0] * n[1] * n[2];
    if (!(nodes <= double(kMaxImplicitGridNodes)))
        throw Error("implicit surface: the field grid would have " + std::to_string(std::llround(std::min(nodes, 1e18))) +
                    " nodes (limit " + std::to_string(kMaxImplicitGridNodes) +
                    "); raise r, lower cells_per_radius or abstract a smaller selection");
    // Every point adds its kernel at the nodes of its support's bounding box (at most 2c + 3 nodes
    // a side, c = cells_per_radius), and every node is visited a few times more to polygonise.
    const double side = 2.0 * p.cells_per_radius + 3.0;
    const double work = double(pt.pts.size()) * side * side * side + kImplicitWorkPerNode * nodes;
    if (!(work <= double(kMaxImplicitWork)))
        throw Error("implicit surface: " + std::to_string(pt.pts.size()) + " points at cells_per_radius " +
                    std::to_string(p.cells_per_radius) + " would take " + std::to_string(std::llround(work / 1e6)) +
                    " million kernel evaluations, over the budget of " + std::to_string(kMaxImplicitWork / 1'000'000) +
                    " million (docs/limits.md \"Work budgets\"); lower cells_per_radius or raise r");
    g.nx = int(n[0]);
    g.ny = int(n[1]);
    g.nz = int(n[2]);
    return g;
}

//! Eq. 6-7 at every node: per z-slab of nodes (in parallel for Fast), the points whose support
//! reaches it, added in index order (the same sums at any thread count).
std::vector<float> sum_field(const Grid& g, const std::vector<glm::vec3>& pts, const ImplicitSurfaceParams& p, const Exec& ex) {
    const int reach = p.cells_per_radius + 1;
    std::vector<std::vector<std::uint32_t>> slab(std::size_t(g.nz));
    for (std::uint32_t idx = 0; idx < pts.size(); ++idx) {
        const int kc = int(std::floor((pts[idx].z - g.origin.z) / g.cell));
        for (int k = std::max(0, kc - reach); k <= std::min(g.nz - 1, kc + reach + 1); ++k) slab[std::size_t(k)].push_back(idx);
    }
    std::vector<float> f(std::size_t(g.nx) * std::size_t(g.ny) * std::size_t(g.nz), 0.0f);
    const float inv_r2 = 1.0f / (p.radius * p.radius);
    auto fill_slab = [&](int k) {
        const float z = g.origin.z + float(k) * g.cell;
        for (const std::uint32_t idx : slab[std::size_t(k)]) {
            const glm::vec3 c = pts[idx];
            const float dz = z - c.z;
            if (dz * dz >= p.radius * p.radius) continue;
            const int i0 = std::max(0, int(std::floor((c.x - p.radius - g.origin.x) / g.cell)));
            const int i1 = std::min(g.nx - 1, int(std::ceil((c.x + p.radius - g.origin.x) / g.cell)));
            const int j0 = std::max(0, int(std::floor((c.y - p.radius - g.origin.y) / g.cell)));
            const int j1 = std::min(g.ny - 1, int(std::ceil((c.y + p.radius - g.origin.y) / g.cell)));
            for (int j = j0; j <= j1; ++j) {
                const float dy = (g.origin.y + float(j) * g.cell) - c.y;
                float* row = f.data() + g.at(0, j, k);
                for (int i = i0; i <= i1; ++i) {
                    const float dx = (g.origin.x + float(i) * g.cell) - c.x;
                    row[i] += kernel(dx * dx + dy * dy + dz * dz, inv_r2);
                }
            }
        }
    };
    for_each_block(ex, std::size_t(g.nz), 1, [&](std::size_t k0, std::size_t k1) {
        for (std::size_t k = k0; k < k1; ++k) fill_slab(int(k));
    });
    return f;
}

//! The threshold (T, or fitted so that fit_inside of the points are inside: just below the
//! quantile of the field at the points, trilinear between the nodes around each) and the fraction
//! of the points inside it, into out.
void fit_threshold(const Grid& g, const std::vector<float>& f, const std::vector<glm::vec3>& pts, const ImplicitSurfaceParams& p,
                   ImplicitSurface& out) {
    std::vector<float> at_point(pts.size());
    for (std::size_t idx = 0; idx < pts.size(); ++idx) {
        const glm::vec3 u = (pts[idx] - g.origin) / g.cell;
        const int i = std::clamp(int(std::floor(u.x)), 0, g.nx - 2), j = std::clamp(int(std::floor(u.y)), 0, g.ny - 2),
                  k = std::clamp(int(std::floor(u.z)), 0, g.nz - 2);
        const glm::vec3 t = glm::clamp(u - glm::vec3(float(i), float(j), float(k)), 0.0f, 1.0f);
        float c[8];
        for (int q = 0; q < 8; ++q) c[q] = f[g.at(i + kCorner[q][0], j + kCorner[q][1], k + kCorner[q][2])];
        at_point[idx] = trilinear(c, t);
    }
    out.threshold = p.threshold;
    if (p.fit_inside > 0.0f && p.fit_inside < 1.0f) {
        std::vector<float> sorted = at_point;
        const std::size_t q = std::min(sorted.size() - 1, std::size_t(double(1.0f - p.fit_inside) * double(sorted.size())));
        std::nth_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(q), sorted.end());
        // Just below the quantile's value, so the points at it count as inside.
        out.threshold = std::nextafter(sorted[q], 0.0f);
        if (!(out.threshold > 0.0f)) out.threshold = std::numeric_limits<float>::min();
    }
    std::size_t inside = 0;
    for (const float v : at_point) inside += v > out.threshold;
    out.inside_fraction = float(double(inside) / double(pts.size()));
}

//! Surface nets' vertices (f > 0 inside): one per cell with corners on both sides, at the mean of
//! its edge crossings, its normal from the trilinear gradient. Returns each cell's vertex (kNone
//! for none), cells indexed (k * (ny - 1) + j) * (nx - 1) + i.
std::vector<std::uint32_t> place_vertices(const Grid& g, const std::vector<float>& f, ImplicitSurface& out) {
    const int cx = g.nx - 1, cy = g.ny - 1, cz = g.nz - 1;
    std::vector<std::uint32_t> vid(std::size_t(cx) * cy * cz, kNone);
    for (int k = 0; k < cz; ++k)
        for (int j = 0; j < cy; ++j)
            for (int i = 0; i < cx; ++i) {
                float c[8];
                int inside = 0;
                for (int q = 0; q < 8; ++q) {
                    c[q] = f[g.at(i + kCorner[q][0], j + kCorner[q][1], k + kCorner[q][2])];
                    inside += c[q] > 0.0f;
                }
                if (inside == 0 || inside == 8) continue;
                glm::vec3 sum(0);
                int m = 0;
                for (const auto& e : kEdge) {
                    const float a = c[e[0]], b = c[e[1]];
                    if ((a > 0.0f) == (b > 0.0f)) continue;
                    const float t = a / (a - b);
                    const glm::vec3 pa(kCorner[e[0]][0], kCorner[e[0]][1], kCorner[e[0]][2]);
                    const glm::vec3 pb(kCorner[e[1]][0], kCorner[e[1]][1], kCorner[e[1]][2]);
                    sum += pa + (pb - pa) * t;
                    ++m;
                }
                const glm::vec3 u = sum / float(m);
                vid[(std::size_t(k) * cy + j) * cx + i] = std::uint32_t(out.positions.size());
                out.positions.push_back(g.node(i, j, k) + u * g.cell);
                const glm::vec3 grad = trilinear_gradient(c, u);
                const float len = glm::length(grad);
                out.normals.push_back(len > 0.0f ? -grad / len : glm::vec3(0, 1, 0));
            }
    return vid;
}

//! Surface nets' faces: one quad per grid edge with a sign change, joining the four cells around
//! it, wound so that its normal points from the inside node to the outside one.
void connect_faces(const Grid& g, const std::vector<float>& f, const std::vector<std::uint32_t>& vid, ImplicitSurface& out) {
    const int cx = g.nx - 1, cy = g.ny - 1;
    auto cell_at = [&](int i, int j, int k) { return (std::size_t(k) * cy + j) * cx + i; };
    auto quad = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d, glm::vec3 outward) {
        if (a == kNone || b == kNone || c == kNone || d == kNone) return;
        const glm::vec3 n = glm::cross(out.positions[c] - out.positions[a], out.positions[d] - out.positions[b]);
        if (glm::dot(n, outward) < 0.0f) std::swap(b, d);
        out.indices.insert(out.indices.end(), {a, b, c, a, c, d});
    };
    for (int k = 1; k < g.nz - 1; ++k)
        for (int j = 1; j < g.ny - 1; ++j)
            for (int i = 1; i < g.nx - 1; ++i) {
                const bool in0 = f[g.at(i, j, k)] > 0.0f;
                if (i + 1 < g.nx && in0 != (f[g.at(i + 1, j, k)] > 0.0f))
                    quad(vid[cell_at(i, j - 1, k - 1)], vid[cell_at(i, j, k - 1)], vid[cell_at(i, j, k)],
                         vid[cell_at(i, j - 1, k)], glm::vec3(in0 ? 1.0f : -1.0f, 0, 0));
                if (j + 1 < g.ny && in0 != (f[g.at(i, j + 1, k)] > 0.0f))
                    quad(vid[cell_at(i - 1, j, k - 1)], vid[cell_at(i, j, k - 1)], vid[cell_at(i, j, k)],
                         vid[cell_at(i - 1, j, k)], glm::vec3(0, in0 ? 1.0f : -1.0f, 0));
                if (k + 1 < g.nz && in0 != (f[g.at(i, j, k + 1)] > 0.0f))
                    quad(vid[cell_at(i - 1, j - 1, k)], vid[cell_at(i, j - 1, k)], vid[cell_at(i, j, k)],
                         vid[cell_at(i - 1, j, k)], glm::vec3(0, 0, in0 ? 1.0f : -1.0f));
            }
}

}  // namespace

ImplicitSurface build_implicit_surface(const std::vector<glm::vec3>& points_in, const ImplicitSurfaceParams& p,
                                       const Exec& ex) {
    check_params(p);
    const Points pt = finite_points(points_in);
    const Grid g = make_grid(pt, p);
    ImplicitSurface out;
    out.grid_nodes = std::int64_t(g.nx) * g.ny * g.nz;
    std::vector<float> f = sum_field(g, pt.pts, p, ex);
    for (const float v : f) out.field_max = std::max(out.field_max, v);
    fit_threshold(g, f, pt.pts, p, out);
    for (float& v : f) v -= out.threshold;  // inside: f > 0 (exactly where the sum exceeds T: IEEE subtraction keeps the sign)
    const std::vector<std::uint32_t> vid = place_vertices(g, f, out);
    connect_faces(g, f, vid, out);
    return out;
}

}  // namespace aq::raster
