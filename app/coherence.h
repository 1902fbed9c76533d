// app/coherence.h — temporal coherence of a rendered frame sequence as numbers (issue 14 item 3;
// docs/coherence.md): `aquarelle coherence`.
//
// Two measures between consecutive frames t-1 and t, both on the stored values of the images (RGB;
// display-encoded for PNG), each a mean absolute change per channel and the fraction of pixels
// whose largest channel change exceeds 1/255:
//  - **static change**: over the pixels whose G-buffer did not change (same object id, linear depth
//    and view-space normal within tolerance) — what moves there is the stylisation alone: a paper
//    or noise pattern fixed to the screen while the scene moves under it ("shower door") or
//    changing by itself (flicker), and neighbourhood effects pulled by what moved nearby;
//  - **motion-compensated change** (the warping error of Lai et al. 2018, "Learning Blind Video
//    Temporal Consistency", with the true motion instead of optical flow): each object pixel of
//    frame t is reprojected through its linear depth and the two frames' cameras into frame t-1;
//    where the point is visible there (same object id, depth within tolerance), the colour of
//    frame t is compared with frame t-1's colour at the reprojected position (bilinear). Disoccluded
//    pixels and pixels leaving the image are excluded and counted.
// Cameras come from each image's provenance manifest (app/manifest.h, "image.camera"); the G-buffer
// (depth.linear, normal, object_id) from the --targets folder of the same run.
#pragma once

#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/image.h"

namespace aq::app {

struct CoherenceParams {
    double static_depth_rel = 1e-4;  //!< |d_t - d_t-1| <= this x d_t: the same depth
    double static_normal = 1e-3;     //!< max |n_t - n_t-1| per component: the same normal
    double warp_depth_rel = 1e-2;    //!< reprojected depth vs frame t-1's depth there: visible
    double threshold = 1.0 / 255.0;  //!< a pixel "changes" when its largest channel change exceeds this
};

//! One frame's G-buffer and camera (column-major matrices as in the manifest).
struct CoherenceFrame {
    const ImageF* image = nullptr;   //!< the stylised image (>= 1 channel; RGB used)
    const ImageF* depth = nullptr;   //!< depth.linear (eye-space distance along -Z)
    const ImageF* normal = nullptr;  //!< normal (view space)
    const ImageF* id = nullptr;      //!< object_id (0 = background)
    glm::dmat4 view{1.0}, projection{1.0};
    bool orthographic = false;
};

struct CoherenceStats {
    long long pixels = 0;                      //!< all pixels of frame t
    long long static_pixels = 0, static_changed = 0;
    double static_sum = 0;                     //!< sum over static pixels of the mean channel change
    long long object_pixels = 0, warped_pixels = 0, warped_changed = 0;
    double warp_sum = 0;
    double static_mean() const { return static_pixels ? static_sum / double(static_pixels) : 0.0; }
    double warp_mean() const { return warped_pixels ? warp_sum / double(warped_pixels) : 0.0; }
    //! Adds another frame pair's counts (totals over a sequence are pixel-weighted).
    void add(const CoherenceStats& o);
};

//! The two measures between prev (t-1) and cur (t). All images of both frames must have one size.
//! Throws aq::Error on mismatched sizes or channel counts.
CoherenceStats frame_coherence(const CoherenceFrame& prev, const CoherenceFrame& cur, const CoherenceParams& p = {});

//! `aquarelle coherence` on files: images of one run (each with its sidecar manifest), taken in the
//! order of the frame numbers their manifests record, and the --targets folder of their run (each
//! target file checked against the SHA-256 its frame's manifest records). Returns the report (one line per frame pair, then the total);
//! writes it as JSON to json_out when not empty. Throws aq::Error.
std::string coherence_report(const std::vector<std::string>& images, const std::string& targets_dir,
                             const CoherenceParams& p, const std::string& json_out);

//! The images of a folder rendered with --frames: every .png/.exr/.tif/.jpg with a sidecar
//! manifest (coherence_report orders them by frame number).
std::vector<std::string> sequence_in_folder(const std::string& dir);

}  // namespace aq::app
