// bench/cli_bench.cpp — what users run (issue 13): the `aquarelle` binary itself, started as a new
// process each iteration (posix_spawn) and rendering into a temporary folder, so process start,
// scene loading, thread-pool start, first-touch allocation, encoding and writing are all counted,
// exactly as a user waits for them. Beside the in-memory kernel benchmarks (BM_RasterFrame,
// pipeline/*, profile/*), docs/performance.md gives the ratio end-to-end / in-memory.
//
//   cli/animation/<scene>/1920x1080/wc18/<png|exr>: --frames 0-11; counters frames/s and s/frame
//   cli/sustained/suzanne/1920x1080/wc18/png: the rate once an animation runs (issue 13 item 2's
//     "sustained"): each iteration renders --frames 0-11 and --frames 0-35 and times only the
//     difference, so process start, loading and the first frame's first-touch cost cancel out;
//     counter cpu_ms/frame: the same difference of the child's CPU time, per frame; counter
//     written_frames/s: in the long run alone, frames 12-35 over the time between the last write
//     of frame 11's file and of frame 35's (file modification times): the same rate measured inside
//     one process, without the start-up variance the difference of two runs carries
//   cli/oneshot/<class>/<size>/<style>/png: one image, from process start to exit, of each asset
//     class of issue 48 item 1: a large mesh (dragon 871k, WC18 1920x1080), a textured model
//     (WaterBottle, two 2048^2 PNG textures, WC18 1280x720), a plant through LD06 (the dense
//     ez-tree oak, 720x720) and a scene file (suzanne.json, WC18 1280x720)
//   cli/oneshot_cached/<class>/<size>/<style>/png: the same one image once the content cache holds
//     the class's scene and foliage (issue 48 item 5: the second one-shot of an asset; one untimed
//     run fills the cache, in the benchmark's own folder). cli/oneshot and every other cli/
//     benchmark run with --no-cache: the first one-shot of an asset
//   cli/steady/<class>/<size>/<style>/png: the same render's steady frame, inside one process: a
//     --frames 0-7 run, timed by its files (frames 2-7 over the time between the writes of frame
//     1's and frame 7's images; the writer overlaps the next frame, so this is the frame period
//     once running). bench/ratios.json holds steady / one-shot per class (docs/performance.md
//     "One-shot renders")
// Every cli/ benchmark reports peak_MB, the child process's peak resident memory.
//
// Scenes from scenes/data and the shared assets (../shared). Wall time (UseRealTime).
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

extern char** environ;

namespace {
namespace fs = std::filesystem;

//! A fresh folder under $TMPDIR (or /tmp) for one benchmark's files.
std::string make_temp_dir() {
    const char* t = std::getenv("TMPDIR");
    std::string tmpl = std::string(t && *t ? t : "/tmp") + "/aq-cli-bench-XXXXXX";
    std::vector<char> buf(tmpl.begin(), tmpl.end());
    buf.push_back('\0');
    return ::mkdtemp(buf.data()) ? std::string(buf.data()) : std::string();
}

//! Runs `aquarelle args...`; returns its exit status (or -1 when it could not be started), the
//! child's peak resident memory in *peak_kb (wait4's ru_maxrss) and, when cpu_s is given, its CPU
//! time (user + system, every thread) in seconds.
int run_cli(const std::vector<std::string>& args, long* peak_kb, double* cpu_s = nullptr) {
    std::vector<char*> argv;
    std::string exe = AQ_CLI_PATH;
    argv.push_back(exe.data());
    std::vector<std::string> copy = args;
    for (auto& a : copy) argv.push_back(a.data());
    argv.push_back(nullptr);
    pid_t pid = 0;
    if (posix_spawn(&pid, exe.c_str(), nullptr, nullptr, argv.data(), environ) != 0) return -1;
    int status = 0;
    struct rusage ru {};
    if (wait4(pid, &status, 0, &ru) != pid) return -1;
    *peak_kb = ru.ru_maxrss;
    if (cpu_s)
        *cpu_s = double(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) + 1e-6 * double(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

//! The counters of a cli/ benchmark (frames per timed second, its inverse, the peak resident memory
//! of the child processes: issue 13 item 6), then the temporary folder removed.
void finish(benchmark::State& st, int frames, long max_peak_kb, const std::string& dir) {
    st.counters["frames/s"] = benchmark::Counter(double(st.iterations()) * frames, benchmark::Counter::kIsRate);
    st.counters["s/frame"] = benchmark::Counter(double(st.iterations()) * frames,
                                                benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
    st.counters["peak_MB"] = benchmark::Counter(double(max_peak_kb) / 1024.0);
    std::error_code ec;
    fs::remove_all(dir, ec);
}

//! Replaces "{out}" in the arguments with the benchmark's temporary folder.
void set_out_dir(std::vector<std::string>& args, const std::string& dir) {
    for (auto& a : args)
        if (auto p = a.find("{out}"); p != std::string::npos) a.replace(p, 5, dir);
}

//! The file of frame f that an animation run (animation(), oneshot_args with frames) writes into dir.
std::string frame_file(const std::string& dir, int f) {
    char name[32];
    std::snprintf(name, sizeof name, "/f_%04d.png", f);
    return dir + name;
}

constexpr int kSteadyFrames = 8;  //!< frames of cli/steady's run (the first two not timed)

//! Runs `args` once per iteration. `steady` (cli/steady, manual time): args render frames
//! 0..kSteadyFrames-1, and an iteration's time is the steady frame, frames 2.. over the time between
//! the writes of frame 1's and the last frame's files.
//! `warm`: one untimed run first (cli/oneshot_cached: it fills the cache).
void bm_cli(benchmark::State& st, std::vector<std::string> args, int frames, bool steady, bool warm) {
    const std::string dir = make_temp_dir();
    if (dir.empty()) {
        st.SkipWithError("cannot create a temporary folder");
        return;
    }
    set_out_dir(args, dir);
    long peak_kb = 0, max_peak_kb = 0;
    if (warm && run_cli(args, &peak_kb) != 0) {
        st.SkipWithError("aquarelle failed (run the command by hand to see why)");
        finish(st, frames, max_peak_kb, dir);
        return;
    }
    for (auto _ : st) {
        const int rc = run_cli(args, &peak_kb);
        max_peak_kb = std::max(max_peak_kb, peak_kb);
        std::error_code e1, e2;
        const auto t1 = steady ? fs::last_write_time(frame_file(dir, 1), e1) : fs::file_time_type{};
        const auto tn = steady ? fs::last_write_time(frame_file(dir, kSteadyFrames - 1), e2) : fs::file_time_type{};
        if (rc != 0 || e1 || e2) {
            st.SkipWithError("aquarelle failed (run the command by hand to see why)");
            break;
        }
        if (steady) st.SetIterationTime(std::max(std::chrono::duration<double>(tn - t1).count() / (kSteadyFrames - 2), 1e-6));
    }
    finish(st, frames, max_peak_kb, dir);
}

constexpr int kAnimationFrames = 12;
constexpr int kSustainedFrames = 36;  //!< the longer run of cli/sustained (24 frames more)

std::vector<std::string> animation(const std::string& scene, const std::string& ext, int frames = kAnimationFrames) {
    return {"render", std::string(AQ_SOURCE_DIR) + "/scenes/data/" + scene, "--frames", "0-" + std::to_string(frames - 1),
            "--width", "1920", "--height", "1080", "--style", "wc18", "--out", "{out}/f_####." + ext, "--quiet", "--no-cache"};
}

//! The sustained rate: the time of the long run minus that of the short one, per extra frame.
void bm_cli_sustained(benchmark::State& st, std::vector<std::string> short_run, std::vector<std::string> long_run, int extra_frames) {
    const std::string dir = make_temp_dir();
    if (dir.empty()) {
        st.SkipWithError("cannot create a temporary folder");
        return;
    }
    set_out_dir(short_run, dir);
    set_out_dir(long_run, dir);
    long peak_kb = 0, max_peak_kb = 0;
    double cpu_sum = 0.0;  // CPU seconds of the long runs minus the short ones
    double written_s = 0.0;  // from frame 11's file written to frame 35's, summed over the long runs
    double cpu = 0.0;
    auto timed = [&](const std::vector<std::string>& args, double* seconds) {
        const auto t0 = std::chrono::steady_clock::now();
        const int rc = run_cli(args, &peak_kb, &cpu);
        *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        max_peak_kb = std::max(max_peak_kb, peak_kb);
        return rc == 0;
    };
    // One untimed run first: on these VMs the first process after an idle spell runs up to 2x
    // slower (the host reclaimed the VM's memory), which made a repetition's short run slower than
    // its long one (a difference clamped to ~0; docs/performance.md "Design decisions that hold").
    {
        double warm = 0.0;
        if (!timed(short_run, &warm)) {
            st.SkipWithError("aquarelle failed (run the command by hand to see why)");
            finish(st, extra_frames, max_peak_kb, dir);
            return;
        }
    }
    for (auto _ : st) {
        double ts = 0.0, tl = 0.0;
        if (!timed(short_run, &ts)) {
            st.SkipWithError("aquarelle failed (run the command by hand to see why)");
            break;
        }
        const double cpu_short = cpu;
        if (!timed(long_run, &tl)) {
            st.SkipWithError("aquarelle failed (run the command by hand to see why)");
            break;
        }
        cpu_sum += cpu - cpu_short;
        st.SetIterationTime(std::max(tl - ts, 1e-6));
        std::error_code e1, e2;
        const auto t11 = fs::last_write_time(frame_file(dir, kAnimationFrames - 1), e1);
        const auto t35 = fs::last_write_time(frame_file(dir, kSustainedFrames - 1), e2);
        if (!e1 && !e2) written_s += std::chrono::duration<double>(t35 - t11).count();
    }
    // The CPU time of a sustained frame (all threads): what bounds the rate on dedicated cores
    // (2 cores: 1000 * 2 / cpu_ms_per_frame frames/s), whatever other tenants take of the host.
    if (st.iterations() > 0)
        st.counters["cpu_ms/frame"] = benchmark::Counter(1e3 * cpu_sum / (double(st.iterations()) * extra_frames));
    if (st.iterations() > 0 && written_s > 0.0)
        st.counters["written_frames/s"] = benchmark::Counter(double(st.iterations()) * extra_frames / written_s);
    finish(st, extra_frames, max_peak_kb, dir);
}

//! An asset class of the one-shot group: what is rendered, in which style, at which size.
struct OneShotClass {
    std::string name, scene, style;
    int width, height;
    std::string id() const { return name + "/" + std::to_string(width) + "x" + std::to_string(height) + "/" + style + "/png"; }
};

std::vector<OneShotClass> oneshot_classes() {
    const std::string shared = std::string(AQ_SHARED_DIR) + "/assets/";
    return {{"dragon_871k", shared + "meshes/stanford_dragon/dragon_871k.glb", "wc18", 1920, 1080},
            {"waterbottle", shared + "gltf/WaterBottle/glTF/WaterBottle.gltf", "wc18", 1280, 720},
            {"ez_oak", shared + "plants/ez-tree/ez_oak_large_dense.glb", "ld06", 720, 720},
            {"suzanne_scene", std::string(AQ_SOURCE_DIR) + "/scenes/data/suzanne.json", "wc18", 1280, 720}};
}

//! The class's render: one image (frames 0), or frames 0..frames-1 as an animation; without the
//! cache, or with it in the benchmark's folder (`cached`).
std::vector<std::string> oneshot_args(const OneShotClass& c, int frames = 0, bool cached = false) {
    std::vector<std::string> a = {"render", c.scene, "--width", std::to_string(c.width), "--height", std::to_string(c.height),
                                  "--style", c.style, "--quiet"};
    if (cached) a.insert(a.end(), {"--cache-dir", "{out}/cache"});
    else a.push_back("--no-cache");
    a.push_back("--out");
    if (frames == 0) {
        a.push_back("{out}/one.png");
    } else {
        a.push_back("{out}/f_####.png");
        a.push_back("--frames");
        a.push_back("0-" + std::to_string(frames - 1));
    }
    return a;
}

void register_all() {
    for (const char* ext : {"png", "exr"})
        benchmark::RegisterBenchmark(("cli/animation/suzanne/1920x1080/wc18/" + std::string(ext)).c_str(), bm_cli,
                                     animation("suzanne.json", ext), kAnimationFrames, false, false)
            ->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
    benchmark::RegisterBenchmark("cli/animation/dragon_202k/1920x1080/wc18/png", bm_cli,
                                 animation("dragon_202k.json", "png"), kAnimationFrames, false, false)
        ->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
    benchmark::RegisterBenchmark("cli/sustained/suzanne/1920x1080/wc18/png", bm_cli_sustained,
                                 animation("suzanne.json", "png"), animation("suzanne.json", "png", kSustainedFrames),
                                 kSustainedFrames - kAnimationFrames)
        ->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(1);
    for (const OneShotClass& c : oneshot_classes()) {
        benchmark::RegisterBenchmark(("cli/oneshot/" + c.id()).c_str(), bm_cli, oneshot_args(c), 1, false, false)
            ->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);
        benchmark::RegisterBenchmark(("cli/oneshot_cached/" + c.id()).c_str(), bm_cli, oneshot_args(c, 0, true), 1, false, true)
            ->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);
        benchmark::RegisterBenchmark(("cli/steady/" + c.id()).c_str(), bm_cli, oneshot_args(c, kSteadyFrames), 1, true, false)
            ->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(1);
    }
}

const int registered = (register_all(), 0);

}  // namespace
