// raster/particles.h — LD06 §4.2 foliage particles (Luft & Deussen 2006, eq. 8-12): particles
// placed around the implicit surface, classified dark / medium / bright by n·l, drawn as
// screen-aligned sprites with the blurred depth test and additive blending into three intensity
// maps in one pass. docs/ld06.md "Particles".
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/exec.h"
#include "core/image.h"
#include "raster/pass.h"

namespace aq::raster {

//! LD06 §4.2 values (Fig. 8 tree; sizes at 720 x 720).
inline constexpr float kLd06Quantity = 30.0f, kLd06Spread = 0.07f, kLd06Scale = 200.0f, kLd06Bias = 5.0f;
inline constexpr float kLd06T0 = -0.5f, kLd06T1 = 0.1f;
//! Ours (defaults): eq. 10 with LD06's ω_scale = 200 makes sprites of 60-140 px for a plant that
//! fills the frame and saturates each map into one blob; 20 and 4 keep separate blotches
//! (docs/ld06.md "Particles"). The paper's values stay available as parameters.
inline constexpr float kParticleSizeScale = 20.0f, kParticleSizeBias = 4.0f;
inline constexpr float kLd06TreeHeight = 23.8f;  //!< h of the Fig. 8 tree
inline constexpr int kLd06SizeReference = 720;   //!< eq. 10's sizes are pixels at 720 x 720
//! Bounds that keep a particle pass finite: count, and estimated fragments (count x largest sprite²).
inline constexpr std::int64_t kMaxParticles = 4'000'000;
inline constexpr double kMaxParticleFragments = 4e9;

struct Particle {
    glm::vec3 position;  //!< world
    glm::vec3 normal;    //!< unit, from the surface vertex
    int cls;             //!< 0 dark, 1 medium, 2 bright (eq. 11)
};

struct ParticleParams {
    float quantity = kLd06Quantity;  //!< ω_quantity of eq. 8
    float spread = kLd06Spread;      //!< ω_spread of eq. 9
    //! h of eq. 8-9 in the units those equations use. Default: every plant is measured as the
    //! paper's Fig. 8 tree (17,000 particles at ω_quantity 30, offsets 0.07·√23.8 tree units scaled
    //! to the plant), so counts do not depend on the model's units (docs/ld06.md "Particles").
    float height = kLd06TreeHeight;
    std::uint32_t seed = 1;
    float t0 = kLd06T0, t1 = kLd06T1;  //!< eq. 11 thresholds, t0 <= t1
    float size_scale = kParticleSizeScale;  //!< ω_scale of eq. 10 (pixels at 720 px; LD06: 200)
    float size_bias = kParticleSizeBias;    //!< ω_bias of eq. 10 (LD06: 5)
    int shape = 0;                     //!< 0 = round blotch (particle_shape), 1 = full square
    float scale = 1.0f;                //!< raster size as a scale of the output size
    DepthTest test = DepthTest::Blurred;
    float delta = 0.05f, beta = 0.05f; //!< β = δ for particles (LD06 §4.2)
    const ImageF* depth_map = nullptr; //!< the camera's (blurred) depth of the abstracted scene
};

//! The rules between the placement parameters (throws aq::Error): quantity, spread and height
//! finite (height > 0), t0 <= t1, and quantity·height² within kMaxParticles. place_particles checks
//! them; the particle pass's validate too, when a pipeline compiles.
void check_particle_params(const ParticleParams& p);

//! Eq. 8-9, 11: N = quantity·height² particles; particle i sits at surface vertex v(i) (a seeded
//! hash of i) plus a seeded random unit vector times spread·√height·(plant height / height),
//! with v's normal and its class by n·l. Pure function of (surface, params, light, plant height).
std::vector<Particle> place_particles(const ImplicitSurface& surface, float plant_height, glm::vec3 light_dir,
                                      const ParticleParams& p);

//! The sprite of eq. 10 in pixels at a raster of width `raster_w`: ((1 - d)·scale + bias)·raster_w/720.
float particle_size_px(float d, float size_scale, float size_bias, int raster_w);

//! Shape of a particle at sprite coordinates (u, v) in [0, 1]²: a round blotch, 1 inside radius
//! 0.4 of the sprite, fading to 0 at 0.5 (ours; LD06 uses a 2D shape texture it does not show).
//! ParticleParams::shape 1 uses 1 everywhere instead (a square sprite).
float particle_shape(float u, float v);

//! Renders `particles` (camera view of ps) into dark, medium and bright maps (1 channel each, at
//! the pass size, background 0): per covered pixel, b' = clamp(f_v·shape + b, 0, 1) in the
//! particle's class map (eq. 12). A sprite of size s covers the pixels whose centres lie in
//! [cx - s/2, cx + s/2) x [cy - s/2, cy + s/2) around the projected centre. Throws aq::Error for
//! invalid parameters or work beyond the documented bounds (checked before drawing).
void render_particles(ImageF& dark, ImageF& medium, ImageF& bright, const PassScene& ps,
                      const std::vector<Particle>& particles, const ParticleParams& p, const Exec& ex = {});

}  // namespace aq::raster
