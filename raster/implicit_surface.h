// raster/implicit_surface.h — LD06 §4.1 tree abstraction (Luft & Deussen 2006, eq. 6-7): the
// foliage's vertices c_j become constraint points of a summed density field
//   D_j(p) = (1 - (|p - c_j| / r)²)²  for |p - c_j| < r, else 0          (eq. 6)
// whose iso-surface  Σ_j D_j(p) = T  replaces the leaves                  (eq. 7)
// triangulated with smooth normals (the field's gradient). docs/ld06.md "Implicit surface".
//
// Polygonisation: naive surface nets on a regular grid (one vertex per cell the surface crosses, at
// the mean of its edge crossings; one quad per crossed grid edge), written here rather than taken
// from OpenVDB (docs/ld06.md says why). Determinism: the field is summed per grid node over the
// points in index order whatever the schedule; vertices and faces are numbered in cell order.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/exec.h"

namespace aq::raster {

//! LD06 Table 1, first tree: T = 83.3, r = 2.8 at tree height h = 37.1 (r = 0.0755 h).
inline constexpr float kLd06Threshold = 83.3f;
inline constexpr float kLd06RadiusPerHeight = 2.8f / 37.1f;
//! Grid nodes allowed for one surface (floats: 128 MiB); larger requests are refused up front.
inline constexpr std::int64_t kMaxImplicitGridNodes = std::int64_t(1) << 25;

//! Work budget of one surface build, in kernel evaluations (points x support nodes, plus
//! kImplicitWorkPerNode per grid node), checked before the grid is allocated (docs/limits.md
//! "Work budgets"). Measured on our 2-core machines, about 1e9 a second: the dense oak (117,120
//! foliage points) is 0.04e9 at its cells_per_radius 2, 0.8e9 at 8 (1 s) and 5.1e9 at 16 (5.4 s),
//! so the budget admits every setting on it and caps a build at about 6 s.
inline constexpr std::uint64_t kMaxImplicitWork = 6'000'000'000ull;
inline constexpr double kImplicitWorkPerNode = 8.0;

struct ImplicitSurfaceParams {
    float threshold = kLd06Threshold;  //!< T of eq. 7, > 0
    float radius = 1.0f;               //!< r of eq. 6 in world units, > 0 (resolve relative values first)
    int cells_per_radius = 2;          //!< grid resolution: cell side = r / cells_per_radius, [1, 16]
    //! When in (0, 1): T is not `threshold` but fitted to the points — the field's value at the
    //! (1 − fit_inside) quantile of the points (field trilinearly interpolated at each point), so
    //! that fraction of the points lies inside the surface (docs/ld06.md "Fitting the abstraction").
    float fit_inside = 0.0f;
};

struct ImplicitSurface {
    std::vector<glm::vec3> positions;  //!< world space
    std::vector<glm::vec3> normals;    //!< unit, outward (towards lower density)
    std::vector<std::uint32_t> indices;  //!< triangle list, counter-clockwise seen from outside
    std::int64_t grid_nodes = 0;         //!< size of the field grid used
    //! The largest summed density Σ D_j at a grid node: the surface is empty exactly when it is not
    //! above T (so a fitted T can be chosen without building the surface again per candidate).
    float field_max = 0;
    float threshold = 0;        //!< the T used (fitted or given)
    float inside_fraction = 0;  //!< share of the finite points where the field exceeds T
};

//! The density field of eq. 6 summed at p (plain loop over every point: the test reference).
float implicit_density(const std::vector<glm::vec3>& points, float radius, glm::vec3 p);

//! Builds the iso-surface Σ D_j = T of `points` (non-finite points are skipped). Throws aq::Error
//! for invalid parameters, no finite point, or a grid beyond kMaxImplicitGridNodes (before
//! allocating it). An empty result (T above the field's maximum) is not an error: the caller
//! decides (the foliage abstraction reports it).
ImplicitSurface build_implicit_surface(const std::vector<glm::vec3>& points, const ImplicitSurfaceParams& p,
                                       const Exec& ex = {});

}  // namespace aq::raster
