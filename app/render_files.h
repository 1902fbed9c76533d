// app/render_files.h — what `aquarelle render` writes: every image of a render job as files
// (--out, --targets EXR, --targets-png), encoded and written on a background thread while the
// next frame renders (app/frame_writer.h). The CLI and the user-level benchmarks
// (bench/cli_bench.cpp) both run this, so the benchmarks measure what users run.
#pragma once

#include <cstddef>
#include <string>

#include "app/render_job.h"

namespace aq::app {

//! Frames rendered ahead of the writer: 2 keeps the writer busy while one frame renders and one
//! waits, and bounds the memory held for writing to two frames' files (docs/performance.md).
inline constexpr std::size_t kFramesInFlight = 2;

//! `pattern` with #### replaced by the zero-padded number (unchanged without ####).
std::string frame_path(const std::string& pattern, int number);

//! Renders the job (run_render) and writes its files. Progress may be reported from the writer
//! thread (calls are serialised). Throws aq::Error; frames complete before a failure stay written.
void render_to_files(RenderJob& job, const Reporter& report, std::size_t frames_in_flight = kFramesInFlight);

}  // namespace aq::app
