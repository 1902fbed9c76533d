// core/targets.h — a named set of images: the G-buffer and every stylization intermediate.
//
// Names follow ../shared/spec/watercolor.md §1: "color", "ctrl.pigment", "ctrl.substrate",
// "ctrl.edge", "ctrl.abstraction", "depth.linear", "normal", "object_id", plus stage outputs.
#pragma once

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
}  // namespace target

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
