// The content cache's folder (core/cache.h): entries round-trip, damage is detected and the entry
// deleted, the size bound evicts the least recently used, failures are reasons, never exceptions.
#include "core/cache.h"

#include <fcntl.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <thread>

#include <gtest/gtest.h>

#include "tests/test_support.h"

namespace aq {
namespace {
namespace fs = std::filesystem;

struct Item {
    std::string name;
    std::vector<float> values;
    std::optional<int> maybe;
};
template <class Ar>
void fields(Ar& ar, Item& i) {
    ar(i.name, i.values, i.maybe);
}

std::string fresh_dir(const std::string& name) {
    const std::string d = test::output_dir() + "/" + name;
    fs::remove_all(d);
    return d;
}

//! Stores an entry of `bytes` payload bytes (a string of them).
std::string store_bytes(const cache::Store& s, const std::string& key, std::size_t bytes) {
    const std::string payload(bytes, 'x');
    return s.store("t", key, [&](archive::Writer& w) { w(payload); });
}

void set_mtime(const std::string& path, std::int64_t seconds) {
    const timespec t[2] = {{seconds, 0}, {seconds, 0}};
    ASSERT_EQ(::utimensat(AT_FDCWD, path.c_str(), t, 0), 0);
}

TEST(Cache, EntriesRoundTripEveryArchivedType) {
    const cache::Store s({fresh_dir("roundtrip"), cache::kDefaultMaxBytes});
    Item in{"leaf", {1.5f, -0.0f, 3e38f}, 7};
    ImageF img(3, 2, 4);
    for (std::size_t i = 0; i < img.num_values(); ++i) img.data()[i] = float(i) * 0.25f;
    std::map<std::string, std::vector<int>> m{{"a", {1, 2}}, {"b", {}}};
    ASSERT_EQ(s.store("t", "k", [&](archive::Writer& w) { w(in, img, m); }), "");
    std::string problem;
    std::optional<cache::Entry> e = s.find("t", "k", &problem);
    ASSERT_TRUE(e) << problem;
    Item out;
    ImageF img2;
    std::map<std::string, std::vector<int>> m2;
    EXPECT_EQ(s.read("t", "k", *e, [&](archive::Reader& r) {
        r(out, img2, m2);
        return true;
    }), "");
    EXPECT_EQ(out.name, in.name);
    EXPECT_EQ(out.values, in.values);
    EXPECT_EQ(out.maybe, in.maybe);
    EXPECT_TRUE(img2 == img);
    EXPECT_EQ(m2, m);
    // Nothing but the entry in the folder (the temporary was renamed).
    int files = 0;
    for (const auto& f : fs::directory_iterator(s.config().dir)) {
        ++files;
        EXPECT_EQ(f.path().extension(), ".aqc");
    }
    EXPECT_EQ(files, 1);
    EXPECT_FALSE(s.find("t", "other"));
}

TEST(Cache, DamagedOrTruncatedEntriesAreReportedDeletedAndNeverRead) {
    const cache::Store s({fresh_dir("damage"), cache::kDefaultMaxBytes});
    for (int kind = 0; kind < 3; ++kind) {
        ASSERT_EQ(store_bytes(s, "k", 1000), "");
        const std::string p = s.path("t", "k");
        if (kind == 0) {  // one payload byte flipped
            std::fstream f(p, std::ios::in | std::ios::out | std::ios::binary);
            f.seekp(500);
            f.put('y');
        } else if (kind == 1) {  // cut short
            fs::resize_file(p, 600);
        } else {  // not an entry at all
            std::ofstream(p, std::ios::trunc) << "hello";
        }
        std::string problem;
        std::optional<cache::Entry> e = s.find("t", "k", &problem);
        if (kind == 0) {  // the header is whole: the damage shows while reading
            ASSERT_TRUE(e);
            std::string payload;
            problem = s.read("t", "k", *e, [&](archive::Reader& r) {
                r(payload);
                return true;
            });
        } else {
            EXPECT_FALSE(e) << kind;
        }
        EXPECT_NE(problem.find(kind == 0 ? "CRC-64" : "truncated"), std::string::npos) << problem;
        EXPECT_FALSE(fs::exists(p)) << "a damaged entry is deleted";
    }
}

TEST(Cache, ReaderRefusesCountsBeyondTheEntry) {
    // A count of 2^40 elements in a 16-byte payload: an error, not a 4 TB allocation.
    const std::uint64_t payload[2] = {std::uint64_t(1) << 40, 0};
    archive::MemorySource m(payload, sizeof payload);
    archive::Reader r(m);
    std::vector<float> v;
    EXPECT_NE(test::error_of([&] { r(v); }).find("exceeds its bytes"), std::string::npos);
    archive::MemorySource m2(payload, 4);
    archive::Reader r2(m2);
    std::string str;
    EXPECT_NE(test::error_of([&] { r2(str); }).find("truncated"), std::string::npos);
}

TEST(Cache, TheSizeBoundEvictsTheLeastRecentlyUsed) {
    const cache::Store s({fresh_dir("lru"), 3500});
    ASSERT_EQ(store_bytes(s, "a", 1000), "");
    ASSERT_EQ(store_bytes(s, "b", 1000), "");
    ASSERT_EQ(store_bytes(s, "c", 1000), "");
    set_mtime(s.path("t", "a"), 1000);
    set_mtime(s.path("t", "b"), 2000);
    set_mtime(s.path("t", "c"), 3000);
    ASSERT_TRUE(s.find("t", "a"));  // a used now: c and b are older
    ASSERT_EQ(store_bytes(s, "d", 1000), "");  // 4 x ~1040 bytes > 3500: the oldest (b) goes
    EXPECT_TRUE(fs::exists(s.path("t", "a")));
    EXPECT_FALSE(fs::exists(s.path("t", "b")));
    EXPECT_TRUE(fs::exists(s.path("t", "c")));
    EXPECT_TRUE(fs::exists(s.path("t", "d")));
    // An entry larger than the bound is not kept, and says so.
    EXPECT_NE(store_bytes(s, "huge", 5000).find("exceeds the bound"), std::string::npos);
    EXPECT_FALSE(fs::exists(s.path("t", "huge")));
    EXPECT_TRUE(fs::exists(s.path("t", "d")));
}

TEST(Cache, AFolderThatCannotBeWrittenIsAReasonNotAnError) {
    const std::string file = test::output_dir() + "/not_a_folder";
    std::ofstream(file) << "x";
    const cache::Store s({file + "/cache", cache::kDefaultMaxBytes});
    EXPECT_NE(store_bytes(s, "k", 10), "");
    EXPECT_FALSE(s.find("t", "k"));
}

TEST(Cache, KeysSeparateTheirParts) {
    EXPECT_EQ(cache::key({"ab", "c"}), cache::key({"ab", "c"}));
    EXPECT_NE(cache::key({"ab", "c"}), cache::key({"a", "bc"}));
    EXPECT_NE(cache::key({"ab"}), cache::key({"ab", ""}));
    EXPECT_EQ(cache::key({"x"}).size(), 64u);
}

TEST(Cache, ConcurrentWritersOfOneKeyLeaveOneWholeEntry) {
    const cache::Store s({fresh_dir("race"), cache::kDefaultMaxBytes});
    std::vector<std::thread> ts;
    for (int i = 0; i < 4; ++i) ts.emplace_back([&] { EXPECT_EQ(store_bytes(s, "k", 200000), ""); });
    for (auto& t : ts) t.join();
    std::optional<cache::Entry> e = s.find("t", "k");
    ASSERT_TRUE(e);
    std::string payload;
    EXPECT_EQ(s.read("t", "k", *e, [&](archive::Reader& r) {
        r(payload);
        return true;
    }), "");
    EXPECT_EQ(payload, std::string(200000, 'x'));
}

TEST(Cache, EnvironmentChoosesTheFolderAndBound) {
    struct Env {
        std::string name;
        std::optional<std::string> old;
        Env(const char* n, const char* v) : name(n) {
            if (const char* o = std::getenv(n)) old = o;
            v ? ::setenv(n, v, 1) : ::unsetenv(n);
        }
        ~Env() { old ? ::setenv(name.c_str(), old->c_str(), 1) : ::unsetenv(name.c_str()); }
    };
    {
        Env a("AQUARELLE_CACHE_DIR", nullptr), x("XDG_CACHE_HOME", "/x"), m("AQUARELLE_CACHE_MAX_MB", "12");
        const auto c = cache::config_from_environment();
        ASSERT_TRUE(c);
        EXPECT_EQ(c->dir, "/x/aquarelle");
        EXPECT_EQ(c->max_bytes, std::uintmax_t(12) << 20);
    }
    {
        Env a("AQUARELLE_CACHE_DIR", "off");
        EXPECT_FALSE(cache::config_from_environment());
    }
    {
        Env a("AQUARELLE_CACHE_DIR", "/c"), m("AQUARELLE_CACHE_MAX_MB", "12x");
        EXPECT_NE(test::error_of([] { (void)cache::config_from_environment(); }).find("AQUARELLE_CACHE_MAX_MB"), std::string::npos);
    }
}

}  // namespace
}  // namespace aq
