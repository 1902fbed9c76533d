// core/io.h — image files through OpenImageIO, written atomically.
//
// PNG: 8-bit, values clamped to [0,1] and rounded (no transfer curve is applied: the watercolor
// maths works on display-referred colour, as MNPR does). EXR: 32-bit float, all channels.
// Every write goes to a temporary file in the destination folder and is renamed over the target
// only when complete, so a failure never leaves a half image over a good one.
#pragma once

#include <string>

#include "core/image.h"

namespace aq {

//! Writes img to path; the format follows the extension (.png, .exr, .tif, ...). Throws aq::Error.
void write_image(const std::string& path, const ImageF& img);

//! Reads any OpenImageIO-readable file as float, keeping up to 4 channels. Throws aq::Error.
ImageF read_image(const std::string& path);

//! Creates the folder (and parents) if missing. Throws aq::Error.
void ensure_directory(const std::string& dir);

//! Replaces characters outside [A-Za-z0-9._-] so a target name is a safe file name.
std::string safe_file_name(const std::string& name);

}  // namespace aq
