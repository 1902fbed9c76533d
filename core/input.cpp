// core/input.cpp — bounded, regular-file-only reads; the path policy; the run's input record.
#include "core/input.h"

#include "core/hash.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <algorithm>
#include <map>
#include <mutex>
#include <set>
#include <utility>

#include "core/image.h"  // aq::Error

namespace aq {
namespace fs = std::filesystem;

namespace {

// The identity of every file read by this process. Function-local statics: files may be read
// during another translation unit's static initialisation (benchmark registration loads presets).
std::mutex& inputs_mutex() {
    static std::mutex m;
    return m;
}
std::set<std::pair<dev_t, ino_t>>& inputs() {
    static std::set<std::pair<dev_t, ino_t>> s;
    return s;
}

void remember(const struct stat& st) {
    std::lock_guard<std::mutex> lock(inputs_mutex());
    inputs().insert({st.st_dev, st.st_ino});
}

// Provenance of every file whose bytes were read (function-local static, as above).
std::map<std::pair<dev_t, ino_t>, InputRecord>& provenance() {
    static std::map<std::pair<dev_t, ino_t>, InputRecord> m;
    return m;
}

//! The live InputCaptures' record lists.
std::vector<std::vector<InputRecord>*>& captures() {
    static std::vector<std::vector<InputRecord>*> v;
    return v;
}

void remember_bytes(const struct stat& st, const std::string& path, const std::vector<unsigned char>& bytes, InputRecord* out) {
    std::error_code ec;
    fs::path abs = fs::absolute(path, ec);
    if (ec) abs = path;
    InputRecord r{abs.lexically_normal().string(), bytes.size(), sha256_hex(bytes.data(), bytes.size())};
    if (out) *out = r;
    std::lock_guard<std::mutex> lock(inputs_mutex());
    for (std::vector<InputRecord>* c : captures()) c->push_back(r);
    inputs().insert({st.st_dev, st.st_ino});
    provenance().emplace(std::make_pair(st.st_dev, st.st_ino), std::move(r));
}

//! Opens read-only and non-blocking (a FIFO with no writer must not block) and checks the opened
//! file, so what is checked is what is read.
int open_checked(const std::string& path, std::uintmax_t max_bytes, const std::string& where, struct stat* st) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (fd < 0) {
        const int e = errno;
        throw Error(where + (e == ENOENT ? ": file not found" : ": cannot be opened: " + std::string(std::strerror(e))));
    }
    if (::fstat(fd, st) != 0) {
        const int e = errno;
        ::close(fd);
        throw Error(where + ": cannot be read: " + std::strerror(e));
    }
    if (!S_ISREG(st->st_mode)) {
        ::close(fd);
        const char* kind = S_ISDIR(st->st_mode)    ? "a folder"
                           : S_ISFIFO(st->st_mode) ? "a FIFO"
                           : S_ISCHR(st->st_mode)  ? "a character device"
                           : S_ISBLK(st->st_mode)  ? "a block device"
                           : S_ISSOCK(st->st_mode) ? "a socket"
                                                   : "not a regular file";
        throw Error(where + ": is " + kind + "; only regular files are read");
    }
    if (std::uintmax_t(st->st_size) > max_bytes) {
        ::close(fd);
        throw Error(where + ": file of " + std::to_string(st->st_size) + " bytes exceeds the limit of " +
                    std::to_string(max_bytes) + " bytes (docs/limits.md)");
    }
    return fd;
}

}  // namespace

std::vector<unsigned char> read_input_file(const std::string& path, std::uintmax_t max_bytes, const std::string& what,
                                           InputRecord* record) {
    const std::string where = what + " '" + path + "'";
    struct stat st {};
    const int fd = open_checked(path, max_bytes, where, &st);
    std::vector<unsigned char> out;
    try {
        out.resize(std::size_t(st.st_size));
    } catch (const std::bad_alloc&) {
        ::close(fd);
        throw Error(where + ": out of memory reading " + std::to_string(st.st_size) + " bytes");
    }
    std::size_t done = 0;
    while (done < out.size()) {
        const ssize_t n = ::read(fd, out.data() + done, out.size() - done);
        if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
        if (n <= 0) {
            const int e = errno;
            ::close(fd);
            throw Error(where + ": read error" + (n < 0 ? ": " + std::string(std::strerror(e)) : ": the file shrank while being read"));
        }
        done += std::size_t(n);
    }
    ::close(fd);
    remember_bytes(st, path, out, record);
    return out;
}

std::string read_input_text(const std::string& path, std::uintmax_t max_bytes, const std::string& what) {
    const std::vector<unsigned char> b = read_input_file(path, max_bytes, what);
    return std::string(b.begin(), b.end());
}

void check_input_file(const std::string& path, std::uintmax_t max_bytes, const std::string& what) {
    // Read (and so hashed for the provenance record) like any input; the caller reads it again.
    (void)read_input_file(path, max_bytes, what);
}

InputCapture::InputCapture() {
    std::lock_guard<std::mutex> lock(inputs_mutex());
    captures().push_back(&records_);
}

InputCapture::~InputCapture() {
    std::lock_guard<std::mutex> lock(inputs_mutex());
    auto& v = captures();
    v.erase(std::find(v.begin(), v.end(), &records_));
}

std::vector<InputRecord> InputCapture::records() const {
    std::lock_guard<std::mutex> lock(inputs_mutex());
    return records_;
}

void forget_input_record(const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) return;
    std::lock_guard<std::mutex> lock(inputs_mutex());
    provenance().erase({st.st_dev, st.st_ino});
}

std::vector<InputRecord> inputs_read() {
    std::vector<InputRecord> v;
    {
        std::lock_guard<std::mutex> lock(inputs_mutex());
        for (const auto& [id, r] : provenance()) v.push_back(r);
    }
    std::sort(v.begin(), v.end(), [](const InputRecord& a, const InputRecord& b) { return a.path < b.path; });
    return v;
}

bool is_input_of_run(const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) return false;
    std::lock_guard<std::mutex> lock(inputs_mutex());
    return inputs().count({st.st_dev, st.st_ino}) != 0;
}

void note_cached_input(const InputRecord& r) {
    std::lock_guard<std::mutex> lock(inputs_mutex());
    for (std::vector<InputRecord>* c : captures()) c->push_back(r);
}

void note_input_of_run(const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0) remember(st);
}

std::string path_policy_violation(const PathPolicy& policy, const std::string& candidate) {
    if (policy.allow_outside) return {};
    std::error_code ec;
    const fs::path root = fs::weakly_canonical(fs::absolute(policy.root.empty() ? fs::path(".") : policy.root, ec), ec);
    if (ec) return "its folder cannot be resolved";
    // weakly_canonical resolves '..' and every symbolic link of the existing part of the path.
    const fs::path real = fs::weakly_canonical(fs::absolute(candidate, ec), ec);
    if (ec) return "the path cannot be resolved";
    const fs::path rel = real.lexically_relative(root);
    if (rel.empty() || *rel.begin() == "..")
        return "it resolves to '" + real.string() + "', outside the model's folder '" + root.string() +
               "' (links, '..' and percent-encoded dots are resolved first; use --allow-outside-files to permit)";
    return {};
}

}  // namespace aq
