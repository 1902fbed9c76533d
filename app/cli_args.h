// app/cli_args.h — strict command-line parsing helpers: every value is checked in full and
// in range, and every error names the option.
#pragma once

#include <charconv>
#include <string>
#include <vector>

#include "core/image.h"

namespace aq::cli {

struct UsageError : Error {
    using Error::Error;
};

class Args {
public:
    Args(int argc, char** argv, int first) {
        for (int i = first; i < argc; ++i) items_.emplace_back(argv[i]);
    }
    explicit Args(std::vector<std::string> items) : items_(std::move(items)) {}
    bool done() const { return pos_ >= items_.size(); }
    const std::string& peek() const { return items_[pos_]; }
    std::string next() { return items_[pos_++]; }
    //! The value after option `opt`; UsageError if missing.
    std::string value(const std::string& opt) {
        if (done()) throw UsageError("option " + opt + " needs a value");
        return next();
    }

private:
    std::vector<std::string> items_;
    std::size_t pos_ = 0;
};

inline long long parse_int(const std::string& opt, const std::string& s, long long lo, long long hi) {
    long long v = 0;
    auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || p != s.data() + s.size())
        throw UsageError("option " + opt + ": '" + s + "' is not an integer");
    if (v < lo || v > hi)
        throw UsageError("option " + opt + ": " + s + " is outside [" + std::to_string(lo) + ", " +
                         std::to_string(hi) + "]");
    return v;
}

inline double parse_double(const std::string& opt, const std::string& s, double lo, double hi) {
    std::size_t used = 0;
    double v = 0;
    try {
        v = std::stod(s, &used);
    } catch (...) {
        used = 0;
    }
    if (used != s.size() || s.empty() || !(v == v))
        throw UsageError("option " + opt + ": '" + s + "' is not a number");
    if (v < lo || v > hi)
        throw UsageError("option " + opt + ": " + s + " is outside [" + std::to_string(lo) + ", " +
                         std::to_string(hi) + "]");
    return v;
}

}  // namespace aq::cli
