// tests/core/mem_reader_test.cpp — core/oiio_mem_reader.h: every read stays inside the buffer,
// whatever offset and length a decoder asks for (OpenImageIO 2.4's own IOMemReader copied from
// before the buffer for -size < offset < 0: fuzz/README.md finding 6). Under ASan (scripts/
// sanitize.sh) any byte read outside the exactly-sized heap buffer below is a failure too.
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <memory>
#include <string>

#include "core/oiio_mem_reader.h"

namespace aq::detail {
namespace {

constexpr std::size_t kSize = 10;

struct Source {
    std::unique_ptr<unsigned char[]> bytes{new unsigned char[kSize]};  // exactly kSize on the heap
    Source() {
        for (std::size_t i = 0; i < kSize; ++i) bytes[i] = static_cast<unsigned char>(100 + i);
    }
};

TEST(BoundedMemReader, ReadsInsideTheBufferAndClampsAtItsEnd) {
    Source src;
    BoundedMemReader r(src.bytes.get(), kSize);
    unsigned char out[kSize] = {};
    ASSERT_EQ(r.pread(out, 4, 2), 4u);
    for (int i = 0; i < 4; ++i) EXPECT_EQ(out[i], 102 + i);
    EXPECT_EQ(r.pread(out, 8, 6), 4u);  // only 4 bytes are left
    EXPECT_EQ(out[3], 109);
    EXPECT_EQ(r.pread(out, std::numeric_limits<std::size_t>::max(), 1), kSize - 1);  // no size + offset overflow
    EXPECT_EQ(r.size(), kSize);
    EXPECT_STREQ(r.proxytype(), "memreader");  // OpenImageIO's JPEG reader accepts only this type
}

TEST(BoundedMemReader, NegativeAndPastTheEndOffsetsReadNothing) {
    Source src;
    BoundedMemReader r(src.bytes.get(), kSize);
    for (int64_t off : {int64_t(-1), int64_t(-2), int64_t(-9), int64_t(-10), std::numeric_limits<int64_t>::min(),
                        int64_t(kSize), int64_t(kSize) + 1, std::numeric_limits<int64_t>::max()}) {
        SCOPED_TRACE(off);
        unsigned char out[4] = {7, 7, 7, 7};
        EXPECT_EQ(r.pread(out, 4, off), 0u);  // OpenImageIO 2.4's reader returned 4 for -2 (from outside)
        EXPECT_EQ(out[0], 7);
    }
}

TEST(BoundedMemReader, SequentialReadsAdvanceAndStopAtTheEnd) {
    Source src;
    BoundedMemReader r(src.bytes.get(), kSize);
    unsigned char out[kSize] = {};
    EXPECT_EQ(r.read(out, 6), 6u);
    EXPECT_EQ(r.tell(), 6);
    EXPECT_EQ(r.read(out, 6), 4u);
    EXPECT_EQ(out[0], 106);
    EXPECT_EQ(r.read(out, 6), 0u);
    ASSERT_TRUE(r.seek(-2));  // a decoder seeking before the start (the BMP of finding 6)
    EXPECT_EQ(r.read(out, 4), 0u);
    EXPECT_EQ(r.tell(), -2);
}

}  // namespace
}  // namespace aq::detail
