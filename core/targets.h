// core/targets.h — a named set of images: the G-buffer and every stylization intermediate.
//
// Names follow ../shared/spec/watercolor.md §1: "color", "ctrl.pigment", "ctrl.substrate",
// "ctrl.edge", "ctrl.abstraction", "depth.linear", "normal", "object_id", plus stage outputs.
#pragma once

#include <iterator>

#include <cstdint>

#include <map>
#include <string>
#include <vector>

#include "core/image.h"

namespace aq {

namespace target {
inline constexpr const char* kColor = "color";
inline constexpr const char* kCtrlPigment = "ctrl.pigment";
inline constexpr const char* kCtrlSubstrate = "ctrl.substrate";
inline constexpr const char* kCtrlEdge = "ctrl.edge";
inline constexpr const char* kCtrlAbstraction = "ctrl.abstraction";
inline constexpr const char* kDepthLinear = "depth.linear";
inline constexpr const char* kNormal = "normal";
inline constexpr const char* kObjectId = "object_id";
inline constexpr const char* kDiffuse = "diffuse";
inline constexpr const char* kSpecular = "specular";

//! The G-buffer the rasterizer writes, named once (used by the rasterizer's allocation and reuse,
//! the synthetic G-buffers of tests, benchmarks and the reference, and the GL twin's check):
//! target, channels, value where nothing is drawn. docs/raster.md "G-buffer".
struct GBufferTarget {
    const char* name;
    int channels;
    bool far_background;  //!< true: the camera's far distance where nothing is drawn; else 0
};
inline constexpr GBufferTarget kGBufferLayout[] = {
    {kColor, 4, false},        {kCtrlPigment, 4, false}, {kCtrlSubstrate, 4, false}, {kCtrlEdge, 4, false},
    {kCtrlAbstraction, 4, false}, {kDepthLinear, 1, true}, {kNormal, 3, false},        {kObjectId, 1, false},
    {kDiffuse, 1, false},      {kSpecular, 1, false},
};
//! Sets of G-buffer targets as bits over kGBufferLayout's order (bit i = kGBufferLayout[i]).
inline constexpr std::uint32_t kAllGBufferTargets = (1u << std::size(kGBufferLayout)) - 1u;
//! The bit of G-buffer target `name` (0 if `name` is not one).
inline std::uint32_t gbuffer_bit(const std::string& name) {
    for (std::size_t i = 0; i < std::size(kGBufferLayout); ++i)
        if (name == kGBufferLayout[i].name) return 1u << i;
    return 0;
}
//! Channels of a G-buffer target (0 if `name` is not one).
inline int gbuffer_channels(const char* name) {
    for (const GBufferTarget& t : kGBufferLayout)
        if (std::string(t.name) == name) return t.channels;
    return 0;
}
}  // namespace target

//! The WC18/MNPR control layout (spec §1 table), named once: four RGBA control targets whose R, G,
//! B channels carry the painted effect parameters below (alpha unused). The scene side (control
//! rules, materials) writes by these names; the stages read the same constants.
namespace control {
inline constexpr int kNumTargets = 4;
inline constexpr const char* kTargets[kNumTargets] = {target::kCtrlPigment, target::kCtrlSubstrate,
                                                      target::kCtrlEdge, target::kCtrlAbstraction};
//! Short names used in scene files ("edge.intensity").
inline constexpr const char* kShortNames[kNumTargets] = {"pigment", "substrate", "edge", "abstraction"};
//! Channel aliases per target (R, G, B), as in scene files.
inline constexpr const char* kChannelNames[kNumTargets][3] = {
    {"variation", "application", "density"},
    {"distortion", "u_incline", "v_incline"},
    {"intensity", "width", "transition"},
    {"detail", "shape", "bleeding"},
};
//! One control value: target index into kTargets and channel.
struct Channel {
    int target;
    int channel;
};
inline constexpr Channel kPigmentVariation{0, 0};     //!< pigment variation (WC18)
inline constexpr Channel kPigmentApplication{0, 1};   //!< granulation / dry brush (pigment_apply)
inline constexpr Channel kPigmentDensity{0, 2};       //!< pigment turbulence (pigment_density)
inline constexpr Channel kSubstrateDistortion{1, 0};  //!< paper distortion (substrate_distort)
inline constexpr Channel kSubstrateUIncline{1, 1};
inline constexpr Channel kSubstrateVIncline{1, 2};
inline constexpr Channel kEdgeIntensity{2, 0};        //!< edge darkening (edge_darken)
inline constexpr Channel kEdgeWidth{2, 1};            //!< edge width (edge_blur/wc18)
inline constexpr Channel kEdgeTransition{2, 2};       //!< gaps & overlaps (gaps_overlaps)
inline constexpr Channel kAbstractionDetail{3, 0};
inline constexpr Channel kAbstractionShape{3, 1};
inline constexpr Channel kAbstractionBleeding{3, 2};  //!< colour bleeding (bleed)
}  // namespace control

class Targets {
public:
    bool has(const std::string& name) const { return images_.count(name) != 0; }
    //! Throws aq::Error naming the missing target and what is there.
    const ImageF& get(const std::string& name) const;
    ImageF& get_mut(const std::string& name);
    //! Checks presence, channel count and size (against `like`, if given) in one call.
    const ImageF& require(const std::string& name, int channels, const ImageF* like = nullptr) const;
    void set(const std::string& name, ImageF img) { images_[name] = std::move(img); }
    ImageF& create(const std::string& name, int w, int h, int channels, float fill = 0.0f);
    void erase(const std::string& name) { images_.erase(name); }
    std::vector<std::string> names() const;
    const std::map<std::string, ImageF>& all() const { return images_; }

private:
    std::map<std::string, ImageF> images_;
};

}  // namespace aq
