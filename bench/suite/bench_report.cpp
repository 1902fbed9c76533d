// bench/suite/bench_report.cpp — `aquarelle_bench_report`: turns one Google Benchmark JSON run of
// the benchmark suite (scripts/bench_suite.sh, docs/bench_suite.md) into a summary JSON and a
// Markdown table — machine, load, compiler, commit, the median of every benchmark — and checks the
// ratios measured in that same run (C++ vs llvmpipe, 2 threads vs 1) against the recorded ones:
// absolute times on shared runners are noise, ratios of two benchmarks of one run are not.
//
// usage: aquarelle_bench_report RUN.json [--markdown OUT.md] [--summary OUT.json]
//                               [--ratios RATIOS.json [--record]]
// Exit status: 0; 4 when a ratio dropped below its recorded value / max_drop; 5 when a benchmark
// reported an error; 1 on bad input; 2 on a usage error.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/build_info.h"
#include "core/io.h"
#include "core/json_file.h"

namespace {

using nlohmann::json;

struct Row {
    std::string name;   //!< run name (without the aggregate suffix)
    double real_ms = 0, cpu_ms = 0;
    int samples = 0;    //!< repetitions behind the median (1: a single run)
    long long iterations = 0;
};

double to_ms(double v, const std::string& unit) {
    if (unit == "ns") return v * 1e-6;
    if (unit == "us") return v * 1e-3;
    if (unit == "s") return v * 1e3;
    return v;  // ms
}

//! One row per benchmark: its "median" aggregate when the run had repetitions with aggregates,
//! else the median of its plain runs (one run: that run).
std::vector<Row> rows_of(const json& run) {
    struct Seen {
        std::vector<Row> runs;
        bool has_median = false;
        Row median;
    };
    std::map<std::string, Seen> seen;
    std::vector<std::string> order;
    for (const json& b : run.at("benchmarks")) {
        const std::string name = b.value("run_name", b.value("name", std::string()));
        const std::string unit = b.value("time_unit", std::string("ns"));
        if (!seen.count(name)) order.push_back(name);
        Seen& s = seen[name];
        Row r{name, to_ms(b.at("real_time").get<double>(), unit), to_ms(b.at("cpu_time").get<double>(), unit), 1,
              b.value("iterations", 0LL)};
        if (b.value("run_type", std::string("iteration")) == "aggregate") {
            if (b.value("aggregate_name", std::string()) != "median") continue;
            r.samples = b.value("repetitions", 0);
            s.median = r;
            s.has_median = true;
        } else {
            s.runs.push_back(r);
        }
    }
    std::vector<Row> out;
    for (const std::string& n : order) {
        Seen& s = seen[n];
        if (s.has_median) {
            out.push_back(s.median);
        } else if (!s.runs.empty()) {
            std::sort(s.runs.begin(), s.runs.end(), [](const Row& a, const Row& b) { return a.real_ms < b.real_ms; });
            Row r = s.runs[s.runs.size() / 2];
            r.samples = int(s.runs.size());
            out.push_back(r);
        }
    }
    return out;
}

std::string fmt(double v, const char* f = "%.3f") {
    char s[64];
    std::snprintf(s, sizeof s, f, v);
    return s;
}

struct RatioResult {
    std::string name, slow, fast;
    double recorded = 0, max_drop = 1, measured = 0;
    bool present = false, dropped = false;
    bool applicable = true;  //!< false when the machine has fewer CPUs than the ratio needs (min_cpus)
};

}  // namespace

int main(int argc, char** argv) {
    std::string in, markdown, summary, ratios_path;
    bool record = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) {
                std::cerr << "aquarelle_bench_report: " << a << " needs a value\n";
                std::exit(2);
            }
            return argv[++i];
        };
        if (a == "--markdown") markdown = value();
        else if (a == "--summary") summary = value();
        else if (a == "--ratios") ratios_path = value();
        else if (a == "--record") record = true;
        else if (a == "--help" || a == "-h") {
            std::cout << "usage: aquarelle_bench_report RUN.json [--markdown OUT.md] [--summary OUT.json] [--ratios "
                         "RATIOS.json [--record]]\n(docs/bench_suite.md)\n";
            return 0;
        } else if (!a.empty() && a[0] == '-') {
            std::cerr << "aquarelle_bench_report: unknown option '" << a << "'\n";
            return 2;
        } else {
            in = a;
        }
    }
    if (in.empty()) {
        std::cerr << "aquarelle_bench_report: no RUN.json given (--help)\n";
        return 2;
    }
    try {
        const json run = aq::read_json_file(in, "benchmark run");
        if (!run.is_object() || !run.contains("benchmarks") || !run.at("benchmarks").is_array())
            throw aq::Error("benchmark run '" + in + "': no 'benchmarks' list (not Google Benchmark JSON output)");
        const json ctx = run.value("context", json::object());
        const std::vector<Row> rows = rows_of(run);
        std::map<std::string, const Row*> by_name;
        for (const Row& r : rows) by_name[r.name] = &r;

        std::vector<RatioResult> ratios;
        json ratio_file;
        if (!ratios_path.empty()) {
            ratio_file = aq::read_json_file(ratios_path, "ratio file");
            for (const json& r : ratio_file.at("ratios")) {
                RatioResult x;
                x.name = r.at("name").get<std::string>();
                x.slow = r.at("slow").get<std::string>();
                x.fast = r.at("fast").get<std::string>();
                x.recorded = r.value("recorded", 0.0);
                x.max_drop = r.value("max_drop", 2.0);
                x.applicable = ctx.value("num_cpus", 0) >= r.value("min_cpus", 0);
                const auto s = by_name.find(x.slow), f = by_name.find(x.fast);
                x.present = s != by_name.end() && f != by_name.end() && f->second->real_ms > 0;
                if (x.present) {
                    x.measured = s->second->real_ms / f->second->real_ms;
                    x.dropped = x.applicable && !record && x.recorded > 0 && x.measured < x.recorded / x.max_drop;
                }
                ratios.push_back(x);
            }
        }

        const aq::BuildInfo& b = aq::build_info();
        std::string load = "?";
        if (ctx.contains("load_avg") && ctx.at("load_avg").is_array() && !ctx.at("load_avg").empty())
            load = fmt(ctx.at("load_avg")[0].get<double>(), "%.2f");
        std::string md = "Benchmark suite run of " + ctx.value("date", std::string("?")) + "\n\n";
        md += "- machine: " + std::to_string(ctx.value("num_cpus", 0)) + " CPUs at " + std::to_string(ctx.value("mhz_per_cpu", 0)) +
              " MHz, load average " + load + " at the start\n";
        md += "- build: aquarelle " + b.describe() + ", " + b.compiler + " " + b.build_type + ", flags " + b.flags + "\n";
        md += "- medians of " + std::to_string(rows.empty() ? 0 : rows.front().samples) +
              " repetition(s) per benchmark (real time; CPU time of the calling thread)\n\n";
        if (!ratios.empty()) {
            md += "| ratio (same run) | measured | recorded | fails below |\n|---|---|---|---|\n";
            for (const RatioResult& r : ratios)
                md += "| " + r.name + " | " + (r.present ? fmt(r.measured, "%.2f") : std::string("(not run)")) + " | " +
                      fmt(r.recorded, "%.2f") + " | " + fmt(r.recorded / r.max_drop, "%.2f") + (r.dropped ? " **DROPPED**" : "") +
                      " |\n";
            md += "\n";
        }
        md += "| benchmark | real ms | CPU ms | iterations (aggregates: repetitions) |\n|---|---|---|---|\n";
        for (const Row& r : rows)
            md += "| `" + r.name + "` | " + fmt(r.real_ms) + " | " + fmt(r.cpu_ms) + " | " + std::to_string(r.iterations) + " |\n";

        json s = {{"date", ctx.value("date", std::string())},
                  {"machine", {{"num_cpus", ctx.value("num_cpus", 0)}, {"mhz_per_cpu", ctx.value("mhz_per_cpu", 0)},
                               {"load_avg", ctx.value("load_avg", json::array())}, {"caches", ctx.value("caches", json::array())}}},
                  {"build", {{"version", b.version}, {"commit", b.commit}, {"dirty", b.dirty}, {"compiler", b.compiler},
                             {"build_type", b.build_type}, {"flags", b.flags}}},
                  {"benchmarks", json::array()},
                  {"ratios", json::array()}};
        for (const Row& r : rows)
            s["benchmarks"].push_back({{"name", r.name}, {"real_ms", r.real_ms}, {"cpu_ms", r.cpu_ms}, {"repetitions", r.samples},
                                       {"iterations", r.iterations}});
        for (const RatioResult& r : ratios)
            s["ratios"].push_back({{"name", r.name}, {"measured", r.present ? json(r.measured) : json(nullptr)},
                                   {"recorded", r.recorded}, {"max_drop", r.max_drop}});
        if (!markdown.empty()) aq::write_file_atomically(markdown, md.data(), md.size());
        if (!summary.empty()) {
            const std::string t = s.dump(2) + "\n";
            aq::write_file_atomically(summary, t.data(), t.size());
        }
        int status = 0;
        // A benchmark that reported an error (SkipWithError: a missing asset, no GL context, a
        // failed render) has rotted: the smoke run must not pass over it.
        for (const json& b : run.at("benchmarks"))
            if (b.value("error_occurred", false)) {
                std::cout << "benchmark '" << b.value("name", std::string()) << "' failed: " << b.value("error_message", std::string())
                          << "\n";
                status = 5;
            }
        for (const RatioResult& r : ratios) {
            if (!r.applicable) {
                std::cout << "ratio '" << r.name << "': not checked on a machine with "
                          << ctx.value("num_cpus", 0) << " CPU(s)\n";
                continue;
            }
            if (!r.present) {  // a renamed or removed benchmark must not silently end its check
                std::cout << "ratio '" << r.name << "': not measured in this run (" << r.slow << " / " << r.fast << ")\n";
                status = 4;
                continue;
            }
            std::cout << "ratio '" << r.name << "': " << fmt(r.measured, "%.3g") << " (recorded " << fmt(r.recorded, "%.3g")
                      << ", fails below " << fmt(r.recorded / r.max_drop, "%.3g") << ")" << (r.dropped ? "  DROPPED" : "") << "\n";
            if (r.dropped) status = 4;
        }
        if (record && !ratios_path.empty()) {
            for (std::size_t i = 0; i < ratios.size(); ++i)
                if (ratios[i].present && ratios[i].applicable) ratio_file["ratios"][i]["recorded"] = std::round(ratios[i].measured * 1000.0) / 1000.0;
            ratio_file["recorded_at"] = {{"date", ctx.value("date", std::string())}, {"commit", b.commit},
                                         {"num_cpus", ctx.value("num_cpus", 0)}, {"load_avg", ctx.value("load_avg", json::array())}};
            // The ratio file is an input of this run, which write_file_atomically refuses to
            // overwrite; recording is the one deliberate rewrite: a new file renamed over it.
            const std::string t = ratio_file.dump(2) + "\n";
            aq::write_file_atomically(ratios_path + ".new", t.data(), t.size());
            std::error_code ec;
            std::filesystem::rename(ratios_path + ".new", ratios_path, ec);
            if (ec) throw aq::Error("cannot replace '" + ratios_path + "': " + ec.message());
            std::cout << "recorded the measured ratios in " << ratios_path << "\n";
        }
        if (status == 4) std::cout << "a ratio dropped beyond its allowed factor (docs/bench_suite.md)\n";
        return status;
    } catch (const std::exception& e) {
        std::cerr << "aquarelle_bench_report: error: " << e.what() << "\n";
        return 1;
    }
}
