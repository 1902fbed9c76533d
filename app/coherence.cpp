// app/coherence.cpp — see coherence.h.
#include "app/coherence.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

#include <nlohmann/json.hpp>

#include "app/manifest.h"
#include "core/hash.h"
#include "core/input.h"
#include "core/io.h"
#include "core/json_file.h"

namespace aq::app {

namespace fs = std::filesystem;
using nlohmann::json;

void CoherenceStats::add(const CoherenceStats& o) {
    pixels += o.pixels;
    static_pixels += o.static_pixels;
    static_changed += o.static_changed;
    static_sum += o.static_sum;
    object_pixels += o.object_pixels;
    warped_pixels += o.warped_pixels;
    warped_changed += o.warped_changed;
    warp_sum += o.warp_sum;
}

namespace {

void check_same(const ImageF& a, const ImageF& ref, int channels, const char* what) {
    if (a.width() != ref.width() || a.height() != ref.height())
        throw Error(std::string("coherence: ") + what + " is " + std::to_string(a.width()) + "x" + std::to_string(a.height()) +
                    ", the image " + std::to_string(ref.width()) + "x" + std::to_string(ref.height()));
    if (a.channels() < channels)
        throw Error(std::string("coherence: ") + what + " has " + std::to_string(a.channels()) + " channel(s), needs " +
                    std::to_string(channels));
}

void check_frame(const CoherenceFrame& f, const ImageF& ref) {
    if (!f.image || !f.depth || !f.normal || !f.id) throw Error("coherence: a frame lacks its image or G-buffer");
    check_same(*f.image, ref, 1, "an image");
    check_same(*f.depth, ref, 1, "depth.linear");
    check_same(*f.normal, ref, 3, "normal");
    check_same(*f.id, ref, 1, "object_id");
}

//! Bilinear sample of channel c at continuous pixel-index coordinates (x, y), clamped to the edge.
double bilinear(const ImageF& im, double x, double y, int c) {
    const int w = im.width(), h = im.height();
    x = std::clamp(x, 0.0, double(w - 1));
    y = std::clamp(y, 0.0, double(h - 1));
    const int x0 = int(x), y0 = int(y);
    const int x1 = std::min(x0 + 1, w - 1), y1 = std::min(y0 + 1, h - 1);
    const double fx = x - x0, fy = y - y0;
    const double a = im.at(x0, y0, c) + (im.at(x1, y0, c) - im.at(x0, y0, c)) * fx;
    const double b = im.at(x0, y1, c) + (im.at(x1, y1, c) - im.at(x0, y1, c)) * fx;
    return a + (b - a) * fy;
}

}  // namespace

CoherenceStats frame_coherence(const CoherenceFrame& prev, const CoherenceFrame& cur, const CoherenceParams& p) {
    if (!cur.image) throw Error("coherence: no image");
    const ImageF& ref = *cur.image;
    check_frame(cur, ref);
    check_frame(prev, ref);
    const int w = ref.width(), h = ref.height();
    const int nc = std::min({3, cur.image->channels(), prev.image->channels()});
    const glm::dmat4 to_prev = prev.view * glm::inverse(cur.view);  // eye(t) -> eye(t-1)
    CoherenceStats s;
    s.pixels = (long long)w * h;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float id = cur.id->at(x, y, 0);
            const double d = cur.depth->at(x, y, 0);
            // Static: the G-buffer did not change here.
            const double dp = prev.depth->at(x, y, 0);
            bool same = id == prev.id->at(x, y, 0) && std::fabs(d - dp) <= p.static_depth_rel * std::fabs(d);
            for (int c = 0; c < 3 && same; ++c)
                same = std::fabs(double(cur.normal->at(x, y, c)) - prev.normal->at(x, y, c)) <= p.static_normal;
            if (same) {
                double sum = 0, mx = 0;
                for (int c = 0; c < nc; ++c) {
                    const double e = std::fabs(double(cur.image->at(x, y, c)) - prev.image->at(x, y, c));
                    sum += e;
                    mx = std::max(mx, e);
                }
                ++s.static_pixels;
                s.static_sum += sum / nc;
                if (mx > p.threshold) ++s.static_changed;
            }
            if (id == 0.0f || !(d > 0.0) || !std::isfinite(d)) continue;
            // Motion-compensated: this pixel's surface point, seen by frame t-1's camera.
            ++s.object_pixels;
            const double nx = 2.0 * (x + 0.5) / w - 1.0, ny = 1.0 - 2.0 * (y + 0.5) / h;
            const glm::dvec4 eye = cur.orthographic
                                       ? glm::dvec4(nx / cur.projection[0][0], ny / cur.projection[1][1], -d, 1.0)
                                       : glm::dvec4(nx * d / cur.projection[0][0], ny * d / cur.projection[1][1], -d, 1.0);
            const glm::dvec4 e1 = to_prev * eye;
            const double d1 = -e1.z;
            if (!(d1 > 0.0)) continue;
            const glm::dvec4 clip = prev.projection * e1;
            if (!(clip.w != 0.0)) continue;
            const double px = (clip.x / clip.w + 1.0) * 0.5 * w - 0.5, py = (1.0 - clip.y / clip.w) * 0.5 * h - 0.5;
            if (!(px >= -0.5 && py >= -0.5 && px < w - 0.5 && py < h - 0.5)) continue;  // left the image
            const int qx = std::clamp(int(std::lround(px)), 0, w - 1), qy = std::clamp(int(std::lround(py)), 0, h - 1);
            if (prev.id->at(qx, qy, 0) != id) continue;  // another object there: disoccluded
            if (std::fabs(double(prev.depth->at(qx, qy, 0)) - d1) > p.warp_depth_rel * d1) continue;  // hidden
            double sum = 0, mx = 0;
            for (int c = 0; c < nc; ++c) {
                const double e = std::fabs(double(cur.image->at(x, y, c)) - bilinear(*prev.image, px, py, c));
                sum += e;
                mx = std::max(mx, e);
            }
            ++s.warped_pixels;
            s.warp_sum += sum / nc;
            if (mx > p.threshold) ++s.warped_changed;
        }
    return s;
}

std::vector<std::string> sequence_in_folder(const std::string& dir) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) throw Error("coherence: '" + dir + "' is not a folder");
    std::vector<std::string> v;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string ext = lower_extension(it->path().string());
        if (ext != ".png" && ext != ".exr" && ext != ".tif" && ext != ".tiff" && ext != ".jpg") continue;
        if (fs::is_regular_file(manifest_path(it->path().string()), ec)) v.push_back(it->path().string());
    }
    std::sort(v.begin(), v.end());
    return v;
}

namespace {

glm::dmat4 matrix(const json& j, const std::string& where) {
    if (!j.is_array() || j.size() != 16) throw Error(where + ": not 16 numbers");
    glm::dmat4 m(1.0);
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) {
            const json& v = j[std::size_t(c * 4 + r)];
            if (!v.is_number()) throw Error(where + ": not a number");
            m[c][r] = v.get<double>();
        }
    return m;
}

struct LoadedFrame {
    std::string path;
    int frame = 0;
    ImageF image, depth, normal, id;
    CoherenceFrame view() const {
        CoherenceFrame f;
        f.image = &image;
        f.depth = &depth;
        f.normal = &normal;
        f.id = &id;
        f.view = view_m;
        f.projection = proj_m;
        f.orthographic = ortho;
        return f;
    }
    glm::dmat4 view_m{1.0}, proj_m{1.0};
    bool ortho = false;
    json run;                                        //!< the manifest's request without its frame
    std::map<std::string, std::string> target_sha;  //!< target name -> SHA-256 of its EXR
};

//! A frame's manifest: its frame number, camera, the request of its run and the SHA-256 its run
//! recorded for each G-buffer target file (outputs of kind "exr").
LoadedFrame read_frame_manifest(const std::string& image) {
    LoadedFrame f;
    f.path = image;
    const std::string mp = manifest_path(image);
    std::error_code ec;
    if (!fs::is_regular_file(mp, ec))
        throw Error("coherence: '" + image + "' has no manifest '" + mp + "' (render it with this version of aquarelle)");
    const json m = read_json_file(mp, "manifest");
    const std::string where = "manifest '" + mp + "'";
    try {
        const json& cam = m.at("image").at("camera");
        f.frame = JsonReader{where}.integer(m.at("image").at("frame"), "image.frame", 0, request_limits::kMaxFrame);
        f.ortho = cam.at("orthographic").get<bool>();
        f.view_m = matrix(cam.at("view"), where + ": image.camera.view");
        f.proj_m = matrix(cam.at("projection"), where + ": image.camera.projection");
        if (!m.at("request").at("targets").get<bool>())
            throw Error(where + ": the run did not write --targets; render again with --targets DIR (the G-buffer is needed)");
        f.run = m.at("request");
        f.run.erase("frame");
        for (const json& o : m.at("outputs"))
            if (o.at("kind") == "exr") f.target_sha[o.at("target").get<std::string>()] = o.at("sha256").get<std::string>();
    } catch (const json::exception& e) {
        throw Error(where + ": no camera, frame or outputs (" + std::string(e.what()) + ")");
    }
    return f;
}

//! One G-buffer target of frame f from the --targets folder, refused unless its bytes are the
//! file the frame's run wrote (the SHA-256 in its manifest): another run's --targets is not read.
ImageF read_target(const LoadedFrame& f, const std::string& dir, const std::string& target) {
    const std::string path = dir + "/" + target + ".exr";
    const auto it = f.target_sha.find(target);
    if (it == f.target_sha.end())
        throw Error("coherence: the manifest of '" + f.path + "' lists no " + target + " target (render with --targets DIR)");
    const std::vector<unsigned char> bytes = read_input_file(path, kMaxModelFileBytes, "G-buffer target");
    if (sha256_hex(bytes.data(), bytes.size()) != it->second)
        throw Error("coherence: '" + path + "' is not the " + target + " target that rendered '" + f.path +
                    "' (its SHA-256 differs from the manifest's): is --targets the folder of another run?");
    return decode_image(bytes.data(), bytes.size(), path);
}

void load_pixels(LoadedFrame& f, const std::string& targets_dir) {
    char sub[32];
    std::snprintf(sub, sizeof sub, "/frame%04d", f.frame);
    const std::string t = targets_dir + sub;
    f.image = read_image(f.path);
    f.depth = read_target(f, t, "depth.linear");
    f.normal = read_target(f, t, "normal");
    f.id = read_target(f, t, "object_id");
}

std::string pct(long long a, long long b) {
    char s[32];
    std::snprintf(s, sizeof s, "%.3f", b ? 100.0 * double(a) / double(b) : 0.0);
    return s;
}

std::string num(double v) {
    char s[32];
    std::snprintf(s, sizeof s, "%.6f", v);
    return s;
}

json stats_json(const CoherenceStats& s) {
    return {{"pixels", s.pixels},
            {"static_pixels", s.static_pixels},
            {"static_mean_abs", s.static_mean()},
            {"static_changed_fraction", s.static_pixels ? double(s.static_changed) / double(s.static_pixels) : 0.0},
            {"object_pixels", s.object_pixels},
            {"warped_pixels", s.warped_pixels},
            {"warp_mean_abs", s.warp_mean()},
            {"warp_changed_fraction", s.warped_pixels ? double(s.warped_changed) / double(s.warped_pixels) : 0.0}};
}

std::string stats_line(const std::string& label, const CoherenceStats& s) {
    return label + "\t" + pct(s.static_pixels, s.pixels) + "\t" + num(s.static_mean()) + "\t" + pct(s.static_changed, s.static_pixels) +
           "\t" + pct(s.warped_pixels, s.object_pixels) + "\t" + num(s.warp_mean()) + "\t" + pct(s.warped_changed, s.warped_pixels) +
           "\n";
}

}  // namespace

std::string coherence_report(const std::vector<std::string>& images, const std::string& targets_dir,
                             const CoherenceParams& p, const std::string& json_out) {
    if (images.size() < 2) throw Error("coherence: needs at least two frames, got " + std::to_string(images.size()));
    if (targets_dir.empty()) throw Error("coherence: needs --targets DIR, the G-buffer folder of the same run");
    std::string out =
        "frames\tstatic px %\tstatic mean |change|\tstatic changed > 1/255 %\twarped px % of object px\twarp mean |change|\twarp "
        "changed > 1/255 %\n";
    json per = json::array();
    CoherenceStats total;
    // Frames pair by the frame numbers their manifests record (never by file name: 9999 -> 10000
    // sorts after 10000 as text), all of one run (one request but for the frame).
    std::vector<LoadedFrame> frames;
    for (const std::string& image : images) frames.push_back(read_frame_manifest(image));
    std::stable_sort(frames.begin(), frames.end(), [](const LoadedFrame& a, const LoadedFrame& b) { return a.frame < b.frame; });
    for (std::size_t i = 1; i < frames.size(); ++i) {
        if (frames[i].frame == frames[i - 1].frame)
            throw Error("coherence: '" + frames[i - 1].path + "' and '" + frames[i].path + "' are both frame " +
                        std::to_string(frames[i].frame));
        if (frames[i].run != frames[0].run)
            throw Error("coherence: '" + frames[i].path + "' and '" + frames[0].path +
                        "' are not frames of one run (their manifests' requests differ beyond the frame number)");
    }
    LoadedFrame prev = std::move(frames[0]);
    load_pixels(prev, targets_dir);
    for (std::size_t i = 1; i < frames.size(); ++i) {
        LoadedFrame cur = std::move(frames[i]);
        load_pixels(cur, targets_dir);
        const CoherenceStats s = frame_coherence(prev.view(), cur.view(), p);
        total.add(s);
        const std::string label = std::to_string(prev.frame) + "->" + std::to_string(cur.frame);
        out += stats_line(label, s);
        json j = stats_json(s);
        j["from"] = prev.frame;
        j["to"] = cur.frame;
        per.push_back(j);
        prev = std::move(cur);
    }
    out += stats_line("total", total);
    if (!json_out.empty()) {
        const json j = {{"frames", per},
                        {"total", stats_json(total)},
                        {"params",
                         {{"static_depth_rel", p.static_depth_rel},
                          {"static_normal", p.static_normal},
                          {"warp_depth_rel", p.warp_depth_rel},
                          {"threshold", p.threshold}}}};
        const std::string text = j.dump(2) + "\n";
        write_file_atomically(json_out, text.data(), text.size());
    }
    return out;
}

}  // namespace aq::app
