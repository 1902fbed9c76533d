// tests/test_support.cpp
#include "tests/test_support.h"

#include <cstdlib>
#include <filesystem>

#include <gtest/gtest.h>

namespace aq::test {

std::string shared_dir() {
    if (const char* e = std::getenv("AQ_SHARED")) return e;
    return AQ_SHARED_DIR;
}

std::string asset(const std::string& rel) {
    std::string p = shared_dir() + "/assets/" + rel;
    if (!std::filesystem::exists(p))
        ADD_FAILURE() << "shared asset missing: " << p
                      << " (tests expect ../shared beside the checkout, or $AQ_SHARED)";
    return p;
}

std::string output_dir() {
    std::string d = AQ_TEST_OUTPUT_DIR;
    std::filesystem::create_directories(d);
    return d;
}

std::string source_dir() { return AQ_SOURCE_DIR; }

}  // namespace aq::test
