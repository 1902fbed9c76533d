// tests/reference/gbuffer_reference_test.cpp — raster::render_gbuffer against the GLSL G-buffer
// twin (reference/gbuffer_twin.h) drawn by OpenGL with the same geometry: coverage, visibility
// (object ids), depth and every interpolated attribute / material output, on scenes built from
// the real models in ../shared/assets and the procedural swatches.
//
// What may differ and why (docs/reference.md "G-buffer"):
//  - coverage at silhouettes: both rasterizers snap to 1/256 px, but GL's fill convention for
//    edges through a pixel centre and its clip/snap arithmetic are its own, and the tremor offset
//    goes through GLSL sin() (a few ulp from glibc at phases ~100 rad): a thin band of pixels;
//  - visibility where two surfaces are within rounding of each other (interpenetrating parts):
//    GL tests window z, raster/ the perspective-interpolated linear depth;
//  - attributes: GL interpolates with its own barycentrics (float), raster/ with fixed-point edge
//    functions; and pow/normalize in the material: small absolute errors.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "core/compare.h"
#include "core/io.h"
#include "reference/gbuffer_twin.h"
#include "scenes/procedural.h"
#include "tests/reference/reference_scenes.h"
#include "tests/reference/reference_support.h"

namespace aq::ref {
namespace {

// Bounds (fractions of all pixels / of pixels covered by the same object in both).
constexpr double kMaxCoverageMismatch = 0.01;   //!< silhouette pixels covered in one image only
constexpr double kMaxIdMismatch = 0.005;        //!< covered in both, different object in front
//! |dz| / z on same-object pixels, 99.9th percentile. raster/ evaluates depth at the 1/256-px
//! snapped vertex positions, GL at its own; on surfaces seen at grazing angles (Suzanne's ears) the
//! depth changes by up to ~1 unit per pixel, so a 1/512-px position difference is ~2e-4 relative.
constexpr double kMaxDepthRelError = 1e-3;
constexpr double kAttrAbsTol = 1.0 / 255.0;     //!< per-value error counted as "off"
constexpr double kMaxAttrOffFraction = 0.01;    //!< same-object values beyond kAttrAbsTol
//! The colour of a scene with textures: the twin filters as the CPU does (texture_filter.glsl:
//! the same mip levels, probes and level of detail) but from GL's derivatives, differences over
//! 2x2 quads, where the CPU's are analytic, so where a texture is minified the level blend and
//! the probes differ slightly (docs/reference.md). Measured at 192x108: Fox 1.1 % of values
//! beyond 1/255 (mean 4.7e-4), BoxTextured (NEAREST_MIPMAP_LINEAR: a texel switch within a level)
//! 2.4 % (mean 5.4e-4).
constexpr double kMaxTexturedColorOffFraction = 0.05;
constexpr double kMaxTexturedColorMean = 1e-3;

struct GStats {
    double coverage_mismatch = 0, id_mismatch = 0, depth_rel_p999 = 0, depth_rel_max = 0;
    std::map<std::string, std::pair<double, double>> attr;  // target -> (max abs, fraction > tol)
    std::map<std::string, double> attr_mean;
};

double percentile(std::vector<double> v, double q) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, std::size_t(q * double(v.size())))];
}

GStats compare_gbuffers(const Targets& a, const Targets& b) {
    GStats s;
    const ImageF& ida = a.get(target::kObjectId);
    const ImageF& idb = b.get(target::kObjectId);
    const int w = ida.width(), h = ida.height();
    std::vector<char> same(std::size_t(w) * h, 0);
    long long cov_mis = 0, both = 0, id_mis = 0;
    std::vector<double> dz;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const bool ca = ida.at(x, y, 0) != 0, cb = idb.at(x, y, 0) != 0;
            if (ca != cb) ++cov_mis;
            if (ca && cb) {
                ++both;
                if (ida.at(x, y, 0) != idb.at(x, y, 0)) ++id_mis;
                else {
                    same[std::size_t(y) * w + x] = 1;
                    const double za = a.get(target::kDepthLinear).at(x, y, 0);
                    const double zb = b.get(target::kDepthLinear).at(x, y, 0);
                    dz.push_back(std::abs(za - zb) / std::max(1e-6, std::abs(za)));
                }
            }
        }
    s.coverage_mismatch = double(cov_mis) / double(w * h);
    s.id_mismatch = both ? double(id_mis) / double(both) : 0.0;
    s.depth_rel_p999 = percentile(dz, 0.999);
    s.depth_rel_max = dz.empty() ? 0 : *std::max_element(dz.begin(), dz.end());
    for (const char* name : {target::kColor, target::kCtrlPigment, target::kCtrlSubstrate, target::kCtrlEdge,
                             target::kCtrlAbstraction, target::kNormal, target::kDiffuse, target::kSpecular}) {
        const ImageF& ia = a.get(name);
        const ImageF& ib = b.get(name);
        double mx = 0, sum = 0;
        long long off = 0, n = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                if (!same[std::size_t(y) * w + x]) continue;
                for (int c = 0; c < ia.channels(); ++c) {
                    const double d = std::abs(double(ia.at(x, y, c)) - double(ib.at(x, y, c)));
                    mx = std::max(mx, std::isfinite(d) ? d : 1e30);
                    sum += d;
                    off += d > kAttrAbsTol;
                    ++n;
                }
            }
        s.attr[name] = {mx, n ? double(off) / double(n) : 0.0};
        s.attr_mean[name] = n ? sum / double(n) : 0.0;
    }
    return s;
}

void write_failure_images(const std::string& scene, const Targets& cpp, const Targets& gl) {
    for (const char* name : {target::kColor, target::kDepthLinear, target::kObjectId, target::kNormal}) {
        const std::string base = test::output_dir() + "/gbuffer." + safe_file_name(scene) + "." + safe_file_name(name);
        write_image(base + ".cpp.exr", cpp.get(name));
        write_image(base + ".gl.exr", gl.get(name));
        write_image(base + ".diff.png", diff_heatmap(cpp.get(name), gl.get(name)));
        std::printf("wrote %s.cpp.exr, .gl.exr, .diff.png\n", base.c_str());
    }
}

class GBufferReference : public ::testing::TestWithParam<std::string> {};

void check_scene(const std::string& name, const std::string& label, const raster::RenderSettings& base) {
    scene::SceneDesc d = load_reference_scene(name);
    const int w = base.width, h = base.height;
    scene::Camera cam = d.camera;
    if (d.camera_auto) cam = scene::frame_bounds(d.scene.world_bounds(), float(w) / float(h), d.auto_view_dir, d.auto_yfov);
    raster::RenderSettings rs = base;
    rs.substrate_color = d.substrate_color;
    const Targets cpp = raster::render_gbuffer(d.scene, cam, rs);
    const Targets gl = render_gbuffer_gl(d.scene, cam, rs);
    const GStats s = compare_gbuffers(cpp, gl);
    std::printf("  gbuffer %-18s %s coverage mismatch %.4f  id mismatch %.4f  depth rel p99.9 %.2g max %.2g\n",
                name.c_str(), label.c_str(), s.coverage_mismatch, s.id_mismatch, s.depth_rel_p999, s.depth_rel_max);
    for (auto& [t, v] : s.attr)
        std::printf("    %-18s mean %.3g max %.3g  fraction > 1/255 %.4f\n", t.c_str(), s.attr_mean.at(t), v.first,
                    v.second);
    bool ok = s.coverage_mismatch <= kMaxCoverageMismatch && s.id_mismatch <= kMaxIdMismatch &&
              s.depth_rel_p999 <= kMaxDepthRelError;
    EXPECT_LE(s.coverage_mismatch, kMaxCoverageMismatch) << name << " " << label;
    EXPECT_LE(s.id_mismatch, kMaxIdMismatch) << name << " " << label;
    EXPECT_LE(s.depth_rel_p999, kMaxDepthRelError) << name << " " << label;
    const bool textured = !d.scene.textures.empty();
    for (auto& [t, v] : s.attr) {
        if (textured && t == target::kColor) {
            EXPECT_LE(v.second, kMaxTexturedColorOffFraction) << name << " " << label << " " << t;
            EXPECT_LE(s.attr_mean.at(t), kMaxTexturedColorMean) << name << " " << label << " " << t;
            ok = ok && v.second <= kMaxTexturedColorOffFraction && s.attr_mean.at(t) <= kMaxTexturedColorMean;
            continue;
        }
        EXPECT_LE(v.second, kMaxAttrOffFraction) << name << " " << label << " " << t;
        ok = ok && v.second <= kMaxAttrOffFraction;
    }
    // Something was drawn: an empty frame would pass every bound above.
    long long covered = 0;
    for (std::size_t i = 0; i < cpp.get(target::kObjectId).num_values(); ++i) covered += cpp.get(target::kObjectId).data()[i] != 0;
    EXPECT_GT(covered, w * h / 50) << name << ": the scene covers almost nothing";
    if (!ok) write_failure_images(name + "." + label, cpp, gl);
}

raster::RenderSettings default_settings() {
    raster::RenderSettings rs;
    rs.width = 192;
    rs.height = 108;
    rs.frame = 3;  // a non-zero tremor phase
    // The twin draws one sample per pixel; the coverage pass has its own twin below.
    rs.antialias = raster::RenderSettings::Antialias::None;
    return rs;
}

TEST_P(GBufferReference, RasterMatchesGlTwin) {
    AQ_REQUIRE_GL();
    check_scene(GetParam(), "default", default_settings());
}

// The other material and vertex paths: object-space turbulence (WC17 eq. 6), back-face culling,
// no tremor, no bleeding displacement, another frame.
TEST(GBufferReferenceOptions, ObjectSpaceTurbulenceCullingNoTremor) {
    AQ_REQUIRE_GL();
    raster::RenderSettings rs = default_settings();
    rs.turbulence = raster::RenderSettings::Turbulence::ObjectSpace;
    rs.cull_backfaces = true;
    check_scene("suzanne", "objturb_cull", rs);
    check_scene("procedural", "objturb_cull", rs);
    rs = default_settings();
    rs.tremor.enabled = false;
    rs.bleed_displacement = false;
    rs.frame = 17;
    check_scene("suzanne", "no_tremor", rs);
}

// The coverage pass (docs/raster.md "Coverage antialiasing") against the GL rasterizer's coverage
// of the same 4x4 sample positions: the twin drawn at 4W x 4H (pixel centres of the finer grid =
// ssaa 4's samples), its alpha averaged over each 4x4 block. No tremor (its offset is in output
// pixels, which the finer grid would change). Within one sample of 16 on nearly every pixel, and
// far closer than one sample per pixel. Measured at 192x108: every pixel within one sample on all
// three, alpha error summed over the pixels 0.2 / 0.4 / 0.1 (one sample per pixel: 61 / 115 / 51).
TEST(GBufferReferenceOptions, CoverageAlphaMatchesGlSamples) {
    AQ_REQUIRE_GL();
    for (const std::string name : {"suzanne", "dragon_202k", "gltf/Fox/glTF/Fox.gltf"}) {
        scene::SceneDesc d = load_reference_scene(name);
        raster::RenderSettings rs = default_settings();
        rs.tremor.enabled = false;
        rs.substrate_color = d.substrate_color;
        const int w = rs.width, h = rs.height, k = 4;
        scene::Camera cam = d.camera;
        if (d.camera_auto) cam = scene::frame_bounds(d.scene.world_bounds(), float(w) / float(h), d.auto_view_dir, d.auto_yfov);
        rs.antialias = raster::RenderSettings::Antialias::Coverage;
        const ImageF cpu = raster::render_gbuffer(d.scene, cam, rs).get(target::kColor);
        rs.antialias = raster::RenderSettings::Antialias::None;
        const ImageF one = raster::render_gbuffer(d.scene, cam, rs).get(target::kColor);
        raster::RenderSettings fine = rs;
        fine.width = w * k;
        fine.height = h * k;
        const ImageF gl = render_gbuffer_gl(d.scene, cam, fine).get(target::kColor);
        int n = 0, near = 0;
        double err = 0, err_one = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                double a = 0;
                for (int sy = 0; sy < k; ++sy)
                    for (int sx = 0; sx < k; ++sx) a += gl.at(x * k + sx, y * k + sy, 3) > 0.0f ? 1.0 : 0.0;
                a /= double(k * k);
                if (a == 0.0 && cpu.at(x, y, 3) == 0.0f) continue;
                ++n;
                const double e = std::abs(double(cpu.at(x, y, 3)) - a);
                near += e <= 1.0 / 16.0 + 1e-6;
                err += e;
                err_one += std::abs(double(one.at(x, y, 3)) - a);
            }
        std::printf("  coverage %-24s %d pixels, %.4f within one sample, alpha error %.1f (one sample per pixel %.1f)\n",
                    name.c_str(), n, double(near) / double(n), err, err_one);
        EXPECT_GT(n, w * h / 50) << name;
        EXPECT_GE(double(near), 0.99 * n) << name;
        EXPECT_LT(err, 0.05 * err_one) << name;
    }
}

INSTANTIATE_TEST_SUITE_P(Scenes, GBufferReference,
                         ::testing::Values("suzanne", "waterbottle", "orientation_test", "procedural", "dragon_202k",
                                           "gltf/Fox/glTF/Fox.gltf", "gltf/BoxTextured/BoxTextured.gltf"),
                         [](const ::testing::TestParamInfo<std::string>& i) {
                             std::string n = i.param;
                             for (char& c : n)
                                 if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                             return n;
                         });

}  // namespace
}  // namespace aq::ref
