// fuzz/fuzz_common.cpp — see fuzz_common.h.
#include "fuzz/fuzz_common.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <oneapi/tbb/global_control.h>

#include "core/oiio.h"

namespace aq::fuzz {
namespace fs = std::filesystem;

namespace {
std::string* g_dir = nullptr;

// Every target runs its code on one thread. With TBB's workers, how a parallel_for splits its
// range depends on which workers join, so the coverage of the same input differed between runs
// (the glTF loader's INITED features 10512 vs 10513 on the same seeds): a fixed-seed run was not
// repeatable, and CI's smoke run (scripts/fuzz.sh --smoke) must be. One thread also makes a finding
// replay along the path that found it. Each library's multi-threaded behaviour is tested in the
// unit tests (same bytes at 1, 2 and 8 threads) and under ASan there (scripts/sanitize.sh).
const oneapi::tbb::global_control g_one_thread(oneapi::tbb::global_control::max_allowed_parallelism, 1);

// The OpenImageIO module (core/oiio.h) is loaded before fuzzing starts, as a linked library would
// be: its coverage counters register with libFuzzer at load, so every input runs with the same
// modules. A target that cannot load it stops here instead of rejecting every image as undecodable.
const bool g_oiio_loaded = [] {
    try {
        aq::oiio();
    } catch (const std::exception& e) {
        std::fprintf(stderr, "fuzz: %s\n", e.what());
        std::abort();
    }
    return true;
}();

void remove_temp_dir() {
    if (!g_dir) return;
    std::error_code ec;
    fs::remove_all(*g_dir, ec);
}
}  // namespace

const std::string& temp_dir() {
    if (!g_dir) {
        // AQ_FUZZ_DIR: a fixed folder (scripts/fuzz.sh --smoke). Paths reach the readers' string
        // handling and libFuzzer's comparison tracing, so a random mkdtemp name made two runs of
        // the same inputs diverge; the smoke run must repeat exactly (docs/testing.md).
        if (const char* fixed = std::getenv("AQ_FUZZ_DIR"); fixed && *fixed) {
            std::error_code ec;
            fs::create_directories(fixed, ec);
            if (ec || !fs::is_directory(fixed)) {
                std::fprintf(stderr, "aq fuzz: cannot create AQ_FUZZ_DIR '%s'\n", fixed);
                std::abort();
            }
            g_dir = new std::string(fixed);
            return *g_dir;
        }
        const char* t = std::getenv("TMPDIR");
        std::string tmpl = std::string(t && *t ? t : "/tmp") + "/aq-fuzz-XXXXXX";
        std::vector<char> buf(tmpl.begin(), tmpl.end());
        buf.push_back('\0');
        if (!::mkdtemp(buf.data())) {
            std::perror("aq fuzz: mkdtemp");
            std::abort();
        }
        g_dir = new std::string(buf.data());
        std::atexit(remove_temp_dir);
    }
    return *g_dir;
}

std::string write_temp(const std::string& name, const std::uint8_t* data, std::size_t size) {
    const std::string path = temp_dir() + "/" + name;
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) {
        std::perror(("aq fuzz: cannot write " + path).c_str());
        std::abort();
    }
    if ((size > 0 && std::fwrite(data, 1, size, f) != size) || std::fclose(f) != 0) {
        std::perror(("aq fuzz: cannot write " + path).c_str());
        std::abort();
    }
    return path;
}

bool verbose() {
    static const bool v = [] {
        const char* e = std::getenv("AQ_FUZZ_VERBOSE");
        return e && *e && *e != '0';
    }();
    return v;
}

void report(const char* what, const char* outcome) { std::fprintf(stderr, "aq fuzz: %s: %s\n", what, outcome); }

void unexpected_exception(const char* what, const char* type, const char* msg) {
    std::fprintf(stderr, "aq fuzz: %s threw %s (not aq::Error): %s\n", what, type, msg);
    std::abort();
}

}  // namespace aq::fuzz
