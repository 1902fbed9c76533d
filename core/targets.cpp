// core/targets.cpp
#include "core/targets.h"

namespace aq {

const ImageF& Targets::get(const std::string& name) const {
    auto it = images_.find(name);
    if (it == images_.end()) {
        std::string have;
        for (auto& [k, v] : images_) have += (have.empty() ? "" : ", ") + k;
        throw Error("missing target '" + name + "' (present: " + (have.empty() ? "none" : have) + ")");
    }
    return it->second;
}

ImageF& Targets::get_mut(const std::string& name) {
    (void)get(name);
    return images_.find(name)->second;
}

const ImageF& Targets::require(const std::string& name, int channels, const ImageF* like) const {
    const ImageF& img = get(name);
    if (img.channels() != channels)
        throw Error("target '" + name + "' has " + std::to_string(img.channels()) +
                    " channels, expected " + std::to_string(channels));
    if (like && !img.same_size(*like))
        throw Error("target '" + name + "' is " + std::to_string(img.width()) + "x" +
                    std::to_string(img.height()) + ", expected " + std::to_string(like->width()) +
                    "x" + std::to_string(like->height()));
    return img;
}

ImageF& Targets::create(const std::string& name, int w, int h, int channels, float fill) {
    images_[name] = ImageF(w, h, channels, fill);
    return images_[name];
}

std::vector<std::string> Targets::names() const {
    std::vector<std::string> out;
    for (auto& [k, v] : images_) out.push_back(k);
    return out;
}

}  // namespace aq
