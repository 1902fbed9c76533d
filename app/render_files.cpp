// app/render_files.cpp — see render_files.h.
#include "app/render_files.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <mutex>

#include "app/frame_writer.h"
#include "app/manifest.h"
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

namespace {

//! The image's targets in pipeline order: what the G-buffer and the paper hold (by name), then
//! what the steps write, in step order; so "the first differing target" of a reproduction is the
//! earliest one in the pipeline.
std::vector<std::string> pipeline_order(const RenderJob& job, const RenderedImage& img) {
    std::map<std::string, std::size_t> rank;
    if (job.stylize && img.style_index < job.compiled.size()) {
        const auto& produced = job.compiled[img.style_index].produced;
        for (std::size_t i = 0; i < produced.size(); ++i) rank.emplace(produced[i], i + 1);
    }
    std::vector<std::string> names;
    for (const auto& [name, t] : img.targets.all()) names.push_back(name);
    std::stable_sort(names.begin(), names.end(), [&](const std::string& a, const std::string& b) {
        const auto ra = rank.find(a), rb = rank.find(b);
        return (ra == rank.end() ? 0 : ra->second) < (rb == rank.end() ? 0 : rb->second);
    });
    return names;
}

//! The manifest's "timings" (non-identity data: reproduce ignores it; docs/provenance.md).
nlohmann::json timings_json(const PhaseTimes& phases) {
    nlohmann::json list = nlohmann::json::array();
    for (const auto& [name, ms] : phases) list.push_back({{"phase", name}, {"ms", std::round(ms * 100.0) / 100.0}});
    return {{"unit", "wall ms"}, {"phases", list}};
}

//! --timings on stderr: one phase a line, then their sum.
std::string timings_text(const std::string& out, const PhaseTimes& phases) {
    std::string s = "timings of " + out + ":";
    int width = 3;
    for (const auto& p : phases) width = std::max(width, int(p.first.size()));
    double sum = 0;
    char line[64];
    auto add = [&](const std::string& name, double ms) {
        std::snprintf(line, sizeof line, " %9.1f ms", ms);
        s += "\n  " + name + std::string(std::size_t(width) - name.size(), ' ') + line;
    };
    for (const auto& [name, ms] : phases) {
        add(name, ms);
        sum += ms;
    }
    add("sum", sum);
    return s;
}

}  // namespace

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
    serialised.info = [&](const std::string& s) {
        std::lock_guard<std::mutex> lock(report_mutex);
        report.info(s);
    };
    bool first_image = true;  // the job's own phases (load, prepare) go with the first image
    FrameWriter writer(frames_in_flight, serialised.progress);
    run_render(job, [&](RenderedImage& img) {
        // The render job reuses its targets for the next frame: the writer gets its own images.
        // Intermediates first, the display image last: a listener waiting for --out sees a
        // complete set.
        FrameWriter::Frame frame;
        std::vector<OutputFile> files;  // what the provenance manifest lists, in frame.files order
        const bool numbered = o.animation || job.sweeping();
        const std::string sub = frame_path(job.sweeping() ? "sweep####" : "frame####", img.index);
        const std::vector<std::string> order = pipeline_order(job, img);
        if (!o.targets_dir.empty()) {
            const std::string dir = numbered ? o.targets_dir + "/" + sub : o.targets_dir;
            ensure_directory(dir);
            for (const std::string& name : order) {
                frame.files.emplace_back(dir + "/" + safe_file_name(name) + ".exr", img.targets.get(name));
                files.push_back({frame.files.back().path, name, "exr"});
            }
        }
        if (!o.targets_png_dir.empty()) {
            const std::string dir = numbered ? o.targets_png_dir + "/" + sub : o.targets_png_dir;
            ensure_directory(dir);
            for (const std::string& name : order) {
                frame.files.emplace_back(dir + "/" + safe_file_name(name) + ".png", visualize_target(name, img.targets.get(name)));
                files.push_back({frame.files.back().path, name, "png"});
            }
        }
        const std::string out = frame_path(o.out, img.index);
        if (img.drop_alpha && !img.converted_ && lower_extension(out) == ".png") {
            // The RGBA painting itself, encoded as RGB by the writer: no full-frame copy on this
            // thread (the next frame's pipeline takes its buffer from the image pool).
            frame.files.emplace_back(out, img.take_final_rgba(), true);
        } else {
            const ImageF& fin = img.final_image();
            if (img.converted_) frame.files.emplace_back(out, std::move(img.converted));
            else frame.files.emplace_back(out, fin);
        }
        files.push_back({out, "", "out"});
        // Provenance (app/manifest.h): embedded in every file without "outputs", then the sidecar.
        nlohmann::json core = manifest_core(job, img);
        frame.description = core.dump();
        frame.compression = o.compression;
        PhaseTimes phases;
        if (o.timings) {
            if (first_image) phases = job.prepare_phases;
            phases.insert(phases.end(), img.phases.begin(), img.phases.end());
        }
        first_image = false;
        frame.after = [core = std::move(core), files = std::move(files), sidecar = manifest_path(out), out,
                       phases = std::move(phases), timings = o.timings,
                       &serialised](const std::vector<std::string>& sha, double write_ms, double commit_ms) mutable {
            nlohmann::json m = manifest_with_outputs(std::move(core), sidecar, files, sha);
            if (timings) {
                phases.emplace_back("encode+write", write_ms);
                phases.emplace_back("commit", commit_ms);
                m["timings"] = timings_json(phases);
                serialised.info(timings_text(out, phases));
            }
            const std::string text = manifest_text(m);
            write_file_atomically(sidecar, text.data(), text.size());
        };
        frame.done_message = img.tag + "wrote " + out;
        frame.claim = manifest_path(out);
        writer.submit(std::move(frame));
    }, serialised);
    writer.finish();
}

}  // namespace aq::app
