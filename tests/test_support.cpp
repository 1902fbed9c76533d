// tests/test_support.cpp
#include "tests/test_support.h"

#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <filesystem>
#include <mutex>
#include <vector>

#include <gtest/gtest.h>

#include "core/image.h"

namespace aq::test {
namespace fs = std::filesystem;

namespace {

std::mutex g_dir_mutex;
std::string g_dir;  // made on first use by output_dir()

//! Removes this process's folder at exit when every test passed; keeps it (and says so) otherwise.
class OutputDirCleanup : public ::testing::Environment {
public:
    void TearDown() override {
        std::lock_guard<std::mutex> lock(g_dir_mutex);
        if (g_dir.empty()) return;
        if (::testing::UnitTest::GetInstance()->Passed() && !std::getenv("AQ_KEEP_TEST_OUTPUT")) {
            std::error_code ec;
            fs::remove_all(g_dir, ec);
        } else {
            std::printf("test output kept in %s\n", g_dir.c_str());
        }
    }
};

[[maybe_unused]] const auto* g_cleanup = ::testing::AddGlobalTestEnvironment(new OutputDirCleanup);

// The `aquarelle` processes a test starts never read or write the user's content cache
// (docs/cache.md): it is off until the test's own folder exists, then inside it (output_dir()).
[[maybe_unused]] const int g_no_user_cache = ::setenv("AQUARELLE_CACHE_DIR", "off", 1);

std::string current_test_name() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string n = info ? std::string(info->test_suite_name()) + "." + info->name() : "process";
    for (char& c : n)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-')) c = '_';
    return n.substr(0, 120);
}

}  // namespace

std::string shared_dir() {
    if (const char* e = std::getenv("AQ_SHARED")) return e;
    return AQ_SHARED_DIR;
}

std::string asset(const std::string& rel) {
    std::string p = shared_dir() + "/assets/" + rel;
    if (!fs::exists(p))
        ADD_FAILURE() << "shared asset missing: " << p
                      << " (tests expect ../shared beside the checkout, or $AQ_SHARED)";
    return p;
}

std::string output_dir() {
    std::lock_guard<std::mutex> lock(g_dir_mutex);
    if (!g_dir.empty()) return g_dir;
    const fs::path root = AQ_TEST_OUTPUT_DIR;
    std::error_code ec;
    fs::create_directories(root, ec);
    std::string templ = (root / (current_test_name() + ".XXXXXX")).string();
    std::vector<char> buf(templ.begin(), templ.end());
    buf.push_back('\0');
    if (!::mkdtemp(buf.data())) {
        ADD_FAILURE() << "cannot create a test output folder under " << root;
        return root.string();
    }
    g_dir = buf.data();
    ::setenv("AQUARELLE_CACHE_DIR", (g_dir + "/cache").c_str(), 1);
    return g_dir;
}

std::string source_dir() { return AQ_SOURCE_DIR; }

std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const aq::Error& e) {
        return e.what();
    }
    return "(no error)";
}

std::string shell_quote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

int run_command(const std::string& command, std::string* output) {
    const std::string log = output_dir() + "/.command.log";
    const int rc = std::system(("(" + command + ") >" + shell_quote(log) + " 2>&1").c_str());
    if (output) *output = file_bytes(log);
    return rc != -1 && WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

std::string file_bytes(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
}

}  // namespace aq::test
