// tests/bench/bench_report_test.cpp — aquarelle_bench_report (docs/bench_suite.md) on small
// hand-written Google Benchmark outputs: medians in the table, a ratio within its factor passes,
// one that dropped beyond it fails with exit 4, a ratio whose benchmarks are missing fails, a
// benchmark that reported an error fails with exit 5, --record stores the measured ratio.
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/test_support.h"

namespace aq {
namespace {

using nlohmann::json;

json bench(const std::string& name, double ms, bool error = false) {
    json b = {{"name", name + "/real_time"}, {"run_name", name + "/real_time"}, {"run_type", "iteration"},
              {"iterations", 3},           {"real_time", ms * 1e6},          {"cpu_time", ms * 1e6},
              {"time_unit", "ns"}};
    if (error) {
        b["error_occurred"] = true;
        b["error_message"] = "asset missing";
    }
    return b;
}

json run(double slow_ms, double fast_ms) {
    json r = {{"context", {{"date", "2026-11-27T03:00:00+00:00"}, {"num_cpus", 2}, {"mhz_per_cpu", 2100}, {"load_avg", {1.5, 1.2, 1.0}}}},
              {"benchmarks", json::array()}};
    // Three repetitions of each, out of order: the report takes the median.
    for (double f : {1.0, 1.2, 0.9}) {
        r["benchmarks"].push_back(bench("slow", slow_ms * f));
        r["benchmarks"].push_back(bench("fast", fast_ms * f));
    }
    return r;
}

void write(const std::string& path, const json& j) { std::ofstream(path) << j.dump(); }

std::string ratios(double recorded, const std::string& slow = "slow/real_time") {
    return json({{"ratios", {{{"name", "slow vs fast"}, {"slow", slow}, {"fast", "fast/real_time"}, {"recorded", recorded}, {"max_drop", 2}}}}})
        .dump();
}

int report(const std::string& dir, const std::string& args, std::string* log) {
    return test::run_command(test::shell_quote(AQ_BENCH_REPORT_EXE) + " " + test::shell_quote(dir + "/run.json") + " " + args, log);
}

TEST(BenchReport, MediansAndRatiosWithinTheirFactorPass) {
    const std::string dir = test::output_dir();
    write(dir + "/run.json", run(100.0, 10.0));  // ratio 10
    std::ofstream(dir + "/ratios.json") << ratios(12.0);  // fails below 6
    std::string log;
    ASSERT_EQ(report(dir, "--markdown " + dir + "/s.md --summary " + dir + "/s.json --ratios " + dir + "/ratios.json", &log), 0) << log;
    const std::string md = test::file_bytes(dir + "/s.md");
    EXPECT_NE(md.find("| `slow/real_time` | 100.000 |"), std::string::npos) << md;  // the median of 90, 100, 120
    EXPECT_NE(md.find("| slow vs fast | 10.00 | 12.00 | 6.00 |"), std::string::npos) << md;
    EXPECT_NE(md.find("2 CPUs"), std::string::npos) << md;
    EXPECT_NE(md.find("commit"), std::string::npos) << md;
    const json s = json::parse(test::file_bytes(dir + "/s.json"));
    EXPECT_DOUBLE_EQ(s.at("ratios")[0].at("measured").get<double>(), 10.0);
    EXPECT_EQ(s.at("benchmarks").size(), 2u);
}

TEST(BenchReport, ADroppedOrMissingRatioFailsAndRecordStoresIt) {
    const std::string dir = test::output_dir();
    write(dir + "/run.json", run(50.0, 10.0));  // ratio 5
    std::ofstream(dir + "/ratios.json") << ratios(12.0);  // fails below 6
    std::string log;
    EXPECT_EQ(report(dir, "--ratios " + dir + "/ratios.json", &log), 4) << log;
    EXPECT_NE(log.find("DROPPED"), std::string::npos) << log;
    std::ofstream(dir + "/ratios.json") << ratios(12.0, "renamed/real_time");
    EXPECT_EQ(report(dir, "--ratios " + dir + "/ratios.json", &log), 4) << log;
    EXPECT_NE(log.find("not measured"), std::string::npos) << log;
    std::ofstream(dir + "/ratios.json") << ratios(12.0);
    EXPECT_EQ(report(dir, "--ratios " + dir + "/ratios.json --record", &log), 0) << log;
    EXPECT_DOUBLE_EQ(json::parse(test::file_bytes(dir + "/ratios.json")).at("ratios")[0].at("recorded").get<double>(), 5.0);
    EXPECT_EQ(report(dir, "--ratios " + dir + "/ratios.json", &log), 0) << log;
}

TEST(BenchReport, ARatioNeedingMoreCpusThanTheMachineHasIsNotChecked) {
    const std::string dir = test::output_dir();
    write(dir + "/run.json", run(50.0, 10.0));  // ratio 5, recorded 12: dropped, but...
    json r = json::parse(ratios(12.0));
    r["ratios"][0]["min_cpus"] = 4;  // ...the run's machine has 2 CPUs
    std::ofstream(dir + "/ratios.json") << r.dump();
    std::string log;
    EXPECT_EQ(report(dir, "--ratios " + dir + "/ratios.json", &log), 0) << log;
    EXPECT_NE(log.find("not checked on a machine with 2 CPU(s)"), std::string::npos) << log;
}

TEST(BenchReport, ABenchmarkErrorFailsAndBadInputIsRefused) {
    const std::string dir = test::output_dir();
    json r = run(100.0, 10.0);
    r["benchmarks"].push_back(bench("rotten", 1.0, true));
    write(dir + "/run.json", r);
    std::string log;
    EXPECT_EQ(report(dir, "", &log), 5) << log;
    EXPECT_NE(log.find("rotten"), std::string::npos) << log;
    EXPECT_NE(log.find("asset missing"), std::string::npos) << log;
    write(dir + "/run.json", json{{"hello", 1}});
    EXPECT_EQ(report(dir, "", &log), 1) << log;
    EXPECT_NE(log.find("not Google Benchmark"), std::string::npos) << log;
}

}  // namespace
}  // namespace aq
