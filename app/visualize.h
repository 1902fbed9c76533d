// app/visualize.h — display versions (PNG) of G-buffer targets and intermediates.
//
// EXR keeps the exact floats for compositing; these mappings only make a target viewable:
//   colour-like targets (color*, bleed, paper): RGB as stored;
//   ctrl.*: signed controls in [-1, 1] mapped to 0.5 + 0.5 v;
//   depth.linear: eye depth normalised between the nearest and farthest covered pixel, near = white;
//   normal: 0.5 + 0.5 n;   object_id: a fixed hashed colour per ID, background black;
//   one-channel targets (edges, depth, diffuse, specular): grey, clamped to [0, 1].
#pragma once

#include <string>

#include "core/image.h"

namespace aq::app {

//! RGB (3-channel) display image of the target `name`.
ImageF visualize_target(const std::string& name, const ImageF& img);

}  // namespace aq::app
