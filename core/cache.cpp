// core/cache.cpp — the content cache's folder: atomic entries with a CRC-64, LRU eviction.
#include "core/cache.h"

#include <dirent.h>
#include <dlfcn.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <isa-l/crc64.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <vector>

#include "core/build_info.h"
#include "core/hash.h"

namespace aq::cache {
namespace fs = std::filesystem;

namespace {

constexpr char kMagic[8] = {'A', 'Q', 'C', 'A', 'C', 'H', 'E', '\n'};
struct Header {
    char magic[8];
    std::uint32_t format;
    std::uint32_t reserved;
    std::uint64_t payload_bytes;
    std::uint64_t crc;  //!< CRC-64 (ECMA-182, reflected: ISA-L crc64_ecma_refl) of the payload
};
static_assert(sizeof(Header) == 32);
constexpr const char* kSuffix = ".aqc";
constexpr const char* kTempPrefix = ".tmp-";
//! A temporary file older than this was left by a killed writer: eviction deletes it.
constexpr auto kStaleTemp = std::chrono::hours(1);

std::string errno_text() { return std::strerror(errno); }

//! The file (executable or shared library) this code was loaded from: its size and modification
//! time name the build in every key, beside the commit (a rebuilt dirty tree keeps its commit).
std::string binary_identity() {
    static const std::string id = [] {
        const BuildInfo& b = build_info();
        std::string s = b.version + "|" + b.commit + (b.dirty ? "|dirty" : "") + "|" + b.flags;
        Dl_info info{};
        struct stat st {};
        const bool found = dladdr(reinterpret_cast<void*>(&binary_identity), &info) != 0 && info.dli_fname &&
                           ::stat(info.dli_fname, &st) == 0;
        if (found || ::stat("/proc/self/exe", &st) == 0)
            s += "|" + std::to_string(st.st_size) + "|" + std::to_string(st.st_mtim.tv_sec) + "." + std::to_string(st.st_mtim.tv_nsec);
        return s;
    }();
    return id;
}

//! Buffered writes to a file descriptor, with the running CRC of everything written.
class FileSink final : public archive::Sink {
public:
    explicit FileSink(int fd) : fd_(fd) { buf_.reserve(kBuffer); }
    void write(const void* data, std::size_t n) override {
        const auto* p = static_cast<const unsigned char*>(data);
        crc_ = crc64_ecma_refl(crc_, p, n);
        total_ += n;
        if (buf_.size() + n > kBuffer) flush();
        if (n >= kBuffer) {
            write_all(p, n);
            return;
        }
        buf_.insert(buf_.end(), p, p + n);
    }
    void flush() {
        write_all(buf_.data(), buf_.size());
        buf_.clear();
    }
    std::uint64_t crc() const { return crc_; }
    std::uint64_t total() const { return total_; }

private:
    static constexpr std::size_t kBuffer = std::size_t(1) << 20;
    void write_all(const unsigned char* p, std::size_t n) {
        while (n) {
            const ssize_t w = ::write(fd_, p, n);
            if (w < 0 && errno == EINTR) continue;
            if (w <= 0) throw Error("cannot write: " + (w < 0 ? errno_text() : std::string("no space")));
            p += w;
            n -= std::size_t(w);
        }
    }
    int fd_;
    std::vector<unsigned char> buf_;
    std::uint64_t crc_ = 0, total_ = 0;
};

//! The payload of an entry, read from its file through a buffer (large reads straight into the
//! destination), with the running CRC of every byte delivered.
class FileSource final : public archive::Source {
public:
    FileSource(int fd, std::size_t payload) : fd_(fd), left_(payload), file_left_(payload) {}
    void read(void* out, std::size_t n) override {
        auto* o = static_cast<unsigned char*>(out);
        const std::size_t want = n;
        const std::size_t from_buf = std::min(n, buf_.size() - pos_);
        if (from_buf) std::memcpy(o, buf_.data() + pos_, from_buf);
        pos_ += from_buf;
        std::size_t done = from_buf;
        if (n - done >= kBuffer) {
            read_all(o + done, n - done);
            done = n;
        }
        while (done < n) {
            const std::size_t fill = std::min(kBuffer, file_left_);
            buf_.resize(fill);
            read_all(buf_.data(), fill);
            pos_ = 0;
            const std::size_t k = std::min(n - done, fill);
            std::memcpy(o + done, buf_.data(), k);
            pos_ = k;
            done += k;
        }
        crc_ = crc64_ecma_refl(crc_, o, want);
        left_ -= want;
    }
    std::size_t left() const override { return left_; }
    std::uint64_t crc() const { return crc_; }

private:
    static constexpr std::size_t kBuffer = std::size_t(64) << 10;
    void read_all(unsigned char* p, std::size_t n) {
        file_left_ -= n;
        while (n) {
            const ssize_t r = ::read(fd_, p, n);
            if (r < 0 && errno == EINTR) continue;
            if (r <= 0) throw Error("cache entry: truncated while read" + (r < 0 ? ": " + errno_text() : std::string()));
            p += r;
            n -= std::size_t(r);
        }
    }
    int fd_;
    std::size_t left_;       //!< payload bytes not yet delivered
    std::size_t file_left_;  //!< payload bytes not yet read from the file
    std::vector<unsigned char> buf_;
    std::size_t pos_ = 0;
    std::uint64_t crc_ = 0;
};

}  // namespace

struct Entry::Impl {
    int fd;
    std::uint64_t crc;
    std::size_t payload;
    FileSource src;
    archive::Reader reader{src};
    Impl(int f, std::uint64_t c, std::size_t p) : fd(f), crc(c), payload(p), src(f, p) {}
    ~Impl() { ::close(fd); }
};

std::optional<Config> config_from_environment() {
    Config c;
    const char* dir = std::getenv("AQUARELLE_CACHE_DIR");
    const char* xdg = std::getenv("XDG_CACHE_HOME");
    const char* home = std::getenv("HOME");
    if (dir && *dir) {
        if (std::string(dir) == "off") return std::nullopt;
        c.dir = dir;
    } else if (xdg && *xdg) {
        c.dir = std::string(xdg) + "/aquarelle";
    } else if (home && *home) {
        c.dir = std::string(home) + "/.cache/aquarelle";
    } else {
        return std::nullopt;
    }
    if (const char* mb = std::getenv("AQUARELLE_CACHE_MAX_MB"); mb && *mb) {
        char* end = nullptr;
        errno = 0;
        const unsigned long long v = std::strtoull(mb, &end, 10);
        if (*end || errno || v > (std::uintmax_t(1) << 44) || mb[0] == '-')
            throw Error("AQUARELLE_CACHE_MAX_MB '" + std::string(mb) + "': expected a whole number of MiB");
        c.max_bytes = std::uintmax_t(v) << 20;
    }
    return c;
}

std::string key(std::initializer_list<std::string_view> parts) {
    std::string buf = "aquarelle-cache " + std::to_string(kFormat) + "\n" + binary_identity() + "\n";
    for (std::string_view p : parts) {
        buf += std::to_string(p.size());
        buf += ':';
        buf.append(p.data(), p.size());
    }
    return sha256_hex(buf.data(), buf.size());
}

Entry::Entry(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Entry::Entry(Entry&& o) noexcept = default;
Entry::~Entry() = default;
archive::Reader& Entry::reader() { return impl_->reader; }
std::size_t Entry::payload_bytes() const { return impl_->payload; }
void Entry::finish() {
    if (impl_->src.left() != 0) throw Error("cache entry: " + std::to_string(impl_->src.left()) + " bytes not read");
    if (impl_->src.crc() != impl_->crc) throw Error("cache entry: CRC-64 mismatch");
}

Store::Store(Config c) : c_(std::move(c)) {}

std::string Store::path(const std::string& kind, const std::string& key) const {
    return c_.dir + "/" + kind + "-" + key + kSuffix;
}

std::optional<Entry> Store::find(const std::string& kind, const std::string& key, std::string* problem) const {
    const std::string p = path(kind, key);
    const int fd = ::open(p.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY);
    if (fd < 0) return std::nullopt;
    struct stat st {};
    std::string bad;
    Header h{};
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        bad = "not a regular file";
    } else if (std::size_t(st.st_size) < sizeof(Header) || ::read(fd, &h, sizeof h) != ssize_t(sizeof h)) {
        bad = "truncated (" + std::to_string(st.st_size) + " bytes)";
    } else if (std::memcmp(h.magic, kMagic, sizeof kMagic) != 0 || h.format != kFormat) {
        bad = "not an entry of this format";
    } else if (h.payload_bytes != std::uint64_t(st.st_size) - sizeof h) {
        bad = "truncated (" + std::to_string(std::uint64_t(st.st_size) - sizeof h) + " of " + std::to_string(h.payload_bytes) +
              " bytes)";
    }
    if (!bad.empty()) {
        ::close(fd);
        ::unlink(p.c_str());
        if (problem) *problem = "cache entry '" + p + "' is " + bad + ": deleted, computed again";
        return std::nullopt;
    }
    (void)::posix_fadvise(fd, 0, 0, POSIX_FADV_SEQUENTIAL);
    (void)::futimens(fd, nullptr);  // used now (LRU); a read-only cache still serves
    return Entry(std::make_unique<Entry::Impl>(fd, h.crc, std::size_t(h.payload_bytes)));
}

std::string Store::read(const std::string& kind, const std::string& key, Entry& e,
                        const std::function<bool(archive::Reader&)>& read) const {
    try {
        if (read(e.reader())) e.finish();
        return {};
    } catch (const Error& err) {
        remove(kind, key);
        std::string what = err.what();
        if (what.rfind("cache entry: ", 0) == 0) what = what.substr(13);
        return "cache entry '" + path(kind, key) + "' is damaged (" + what + "): deleted, computed again";
    }
}

void Store::remove(const std::string& kind, const std::string& key) const { ::unlink(path(kind, key).c_str()); }

std::string Store::store(const std::string& kind, const std::string& key,
                         const std::function<void(archive::Writer&)>& fill) const {
    std::error_code ec;
    fs::create_directories(c_.dir, ec);
    if (ec) return "not cached: folder '" + c_.dir + "' cannot be created: " + ec.message();
    std::string tmp = c_.dir + "/" + kTempPrefix + kind + "-XXXXXX";
    const int fd = ::mkostemp(tmp.data(), O_CLOEXEC);
    if (fd < 0) return "not cached: folder '" + c_.dir + "' is not writable: " + errno_text();
    std::string why;
    try {
        Header h{};
        std::memcpy(h.magic, kMagic, sizeof kMagic);
        h.format = kFormat;
        if (::write(fd, &h, sizeof h) != ssize_t(sizeof h)) throw Error("cannot write: " + errno_text());
        FileSink sink(fd);
        archive::Writer w(sink);
        fill(w);
        sink.flush();
        h.payload_bytes = sink.total();
        h.crc = sink.crc();
        if (h.payload_bytes + sizeof h > c_.max_bytes)
            throw Error("an entry of " + std::to_string(h.payload_bytes >> 20) + " MiB exceeds the bound of " +
                        std::to_string(c_.max_bytes >> 20) + " MiB");
        if (::pwrite(fd, &h, sizeof h, 0) != ssize_t(sizeof h)) throw Error("cannot write: " + errno_text());
    } catch (const std::exception& e) {
        why = e.what();
    }
    if (::close(fd) != 0 && why.empty()) why = "cannot write: " + errno_text();
    const std::string final_path = path(kind, key);
    if (why.empty() && ::rename(tmp.c_str(), final_path.c_str()) != 0) why = "cannot rename: " + errno_text();
    if (!why.empty()) {
        ::unlink(tmp.c_str());
        return "not cached in '" + c_.dir + "': " + why;
    }
    evict(final_path);
    return {};
}

void Store::evict(const std::string& keep) const {
    struct Item {
        std::int64_t mtime_ns;
        std::uintmax_t bytes;
        std::string path;
    };
    std::vector<Item> items;
    std::uintmax_t total = 0;
    const auto now = std::chrono::system_clock::now().time_since_epoch();
    const std::int64_t stale_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(now - kStaleTemp).count();
    DIR* d = ::opendir(c_.dir.c_str());
    if (!d) return;
    while (const dirent* e = ::readdir(d)) {
        const std::string name = e->d_name;
        const bool entry = name.size() > 4 && name.compare(name.size() - 4, 4, kSuffix) == 0;
        const bool temp = name.rfind(kTempPrefix, 0) == 0;
        if (!entry && !temp) continue;
        const std::string p = c_.dir + "/" + name;
        struct stat st {};
        if (::lstat(p.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) continue;
        const std::int64_t t = std::int64_t(st.st_mtim.tv_sec) * 1'000'000'000 + st.st_mtim.tv_nsec;
        if (temp) {
            if (t < stale_ns) ::unlink(p.c_str());
            continue;
        }
        items.push_back({t, std::uintmax_t(st.st_size), p});
        total += std::uintmax_t(st.st_size);
    }
    ::closedir(d);
    if (total <= c_.max_bytes) return;
    std::sort(items.begin(), items.end(), [](const Item& a, const Item& b) {
        return a.mtime_ns != b.mtime_ns ? a.mtime_ns < b.mtime_ns : a.path < b.path;
    });
    for (const Item& it : items) {
        if (total <= c_.max_bytes) break;
        if (it.path == keep) continue;
        if (::unlink(it.path.c_str()) == 0 || errno == ENOENT) total -= it.bytes;
    }
}

}  // namespace aq::cache
