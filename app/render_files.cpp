// app/render_files.cpp — see render_files.h.
#include "app/render_files.h"

#include <cstdio>
#include <mutex>

#include "app/frame_writer.h"
#include "app/visualize.h"
#include "core/io.h"

namespace aq::app {

std::string frame_path(const std::string& pattern, int number) {
    const auto pos = pattern.find("####");
    if (pos == std::string::npos) return pattern;
    char num[32];
    std::snprintf(num, sizeof num, "%04d", number);
    return pattern.substr(0, pos) + num + pattern.substr(pos + 4);
}

void render_to_files(RenderJob& job, const Reporter& report, std::size_t frames_in_flight) {
    const RenderOptions& o = job.options;
    std::mutex report_mutex;  // the writer thread reports too
    Reporter serialised;
    serialised.progress = [&](const std::string& s) {
        std::lock_guard<std::mutex> lock(report_mutex);
        report.progress(s);
    };
    serialised.warning = [&](const std::string& s) {
        std::lock_guard<std::mutex> lock(report_mutex);
        report.warning(s);
    };
    FrameWriter writer(frames_in_flight, serialised.progress);
    run_render(job, [&](RenderedImage& img) {
        // The render job reuses its targets for the next frame: the writer gets its own images.
        // Intermediates first, the display image last: a listener waiting for --out sees a
        // complete set.
        FrameWriter::Frame frame;
        const bool numbered = o.animation || job.sweeping();
        const std::string sub = frame_path(job.sweeping() ? "sweep####" : "frame####", img.index);
        if (!o.targets_dir.empty()) {
            const std::string dir = numbered ? o.targets_dir + "/" + sub : o.targets_dir;
            ensure_directory(dir);
            for (const auto& [name, t] : img.targets.all())
                frame.files.emplace_back(dir + "/" + safe_file_name(name) + ".exr", t);
        }
        if (!o.targets_png_dir.empty()) {
            const std::string dir = numbered ? o.targets_png_dir + "/" + sub : o.targets_png_dir;
            ensure_directory(dir);
            for (const auto& [name, t] : img.targets.all())
                frame.files.emplace_back(dir + "/" + safe_file_name(name) + ".png", visualize_target(name, t));
        }
        const std::string out = frame_path(o.out, img.index);
        if (img.converted_) frame.files.emplace_back(out, std::move(img.converted));
        else frame.files.emplace_back(out, img.final_image());
        frame.done_message = img.tag + "wrote " + out;
        writer.submit(std::move(frame));
    }, serialised);
    writer.finish();
}

}  // namespace aq::app
