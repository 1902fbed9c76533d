// tests/core/image_test.cpp — border rules, size limits, typed views.
#include "core/image.h"

#include <gtest/gtest.h>

namespace aq {

TEST(Border, ClampAndMirrorMapIntoRange) {
    EXPECT_EQ(resolve_border(-3, 5, Border::Clamp), 0);
    EXPECT_EQ(resolve_border(7, 5, Border::Clamp), 4);
    EXPECT_EQ(resolve_border(-1, 5, Border::Mirror), 1);
    EXPECT_EQ(resolve_border(5, 5, Border::Mirror), 3);
    EXPECT_EQ(resolve_border(-4, 5, Border::Mirror), 4);
    EXPECT_EQ(resolve_border(9, 5, Border::Mirror), 1);
    for (int i = -40; i < 40; ++i) {
        for (int n : {1, 2, 3, 7}) {
            int m = resolve_border(i, n, Border::Mirror);
            EXPECT_GE(m, 0);
            EXPECT_LT(m, n);
        }
    }
}

TEST(ImageF, RefusesAbsurdSizesBeforeAllocating) {
    EXPECT_THROW(ImageF(0, 10, 4), Error);
    EXPECT_THROW(ImageF(-5, 10, 4), Error);
    EXPECT_THROW(ImageF(kMaxImageSide + 1, 1, 1), Error);
    EXPECT_THROW(ImageF(16384, 16384, 4), Error);  // 256 Mpx > limit
    EXPECT_THROW(ImageF(4, 4, 5), Error);
    EXPECT_NO_THROW(ImageF(4, 4, 1));
}

// A moved-from image is empty, so ensure_output() allocates instead of writing into it: with the
// defaulted moves it kept its 200 x 120 x 3 shape without storage and the CLI's animation path
// crashed (SIGSEGV) writing frame 2's converted image.
TEST(ImageF, MovedFromImageIsEmptyAndEnsureOutputAllocatesAgain) {
    ImageF a(20, 12, 3, 0.5f);
    ImageF b(std::move(a));
    EXPECT_TRUE(a.empty());  // NOLINT(bugprone-use-after-move): the moved-from state is the point
    EXPECT_EQ(a.width(), 0);
    EXPECT_EQ(a.channels(), 0);
    EXPECT_EQ(a.data(), nullptr);
    ensure_output(a, 20, 12, 3);
    ASSERT_NE(a.data(), nullptr);
    a.at(19, 11, 2) = 1.0f;
    ImageF c;
    c = std::move(b);
    EXPECT_TRUE(b.empty());  // NOLINT(bugprone-use-after-move)
    EXPECT_EQ(b.height(), 0);
    EXPECT_EQ(c.width(), 20);
    EXPECT_FLOAT_EQ(c.at(19, 11, 2), 0.5f);
}

// ImageF::stamp (the rasterizer's background tiles kept between frames rely on it): it moves
// with the storage, a copy starts unstamped, and every mutable access clears it; const access
// keeps it.
TEST(ImageF, ContentStampMovesWithTheStorageAndMutableAccessClearsIt) {
    ImageF a(4, 3, 2, 0.0f);
    EXPECT_EQ(a.stamp(), 0u);
    a.set_stamp(42);
    const ImageF& ca = a;
    (void)ca.data();
    (void)ca.at(1, 1, 1);
    (void)ca.view<glm::vec2>();
    EXPECT_EQ(a.stamp(), 42u) << "const access cleared the stamp";
    ImageF b(std::move(a));
    EXPECT_EQ(b.stamp(), 42u);
    EXPECT_EQ(a.stamp(), 0u);  // NOLINT(bugprone-use-after-move)
    ImageF c;
    c = std::move(b);
    EXPECT_EQ(c.stamp(), 42u);
    EXPECT_EQ(b.stamp(), 0u);  // NOLINT(bugprone-use-after-move)
    const ImageF copy(c);
    EXPECT_EQ(copy.stamp(), 0u) << "a copy is not the stamping writer's image";
    ImageF assigned;
    assigned = c;
    EXPECT_EQ(assigned.stamp(), 0u);
    (void)c.data();
    EXPECT_EQ(c.stamp(), 0u) << "data()";
    c.set_stamp(7);
    c.at(0, 0, 0) = 1.0f;
    EXPECT_EQ(c.stamp(), 0u) << "at()";
    c.set_stamp(7);
    (void)c.view<glm::vec2>();
    EXPECT_EQ(c.stamp(), 0u) << "view()";
}

TEST(ImageF, ViewChannelCountIsChecked) {
    ImageF img(3, 2, 4, 0.5f);
    EXPECT_NO_THROW(img.view<glm::vec4>());
    EXPECT_THROW(img.view<float>(), Error);
    auto v = img.view<glm::vec4>();
    v(2, 1) = glm::vec4(1, 2, 3, 4);
    EXPECT_EQ(img.at(2, 1, 2), 3.0f);
}

}  // namespace aq

namespace aq {
namespace {

// The buffer pool hands a freed large buffer to the next image of the same size; a filled image
// must still hold its fill value everywhere, whatever the recycled buffer contained.
TEST(ImagePool, RecycledBuffersAreRefilledAndBounded) {
    image_pool_release();
    const float* first = nullptr;
    {
        ImageF a(1024, 1024, 4, 7.0f);  // 16 MiB: pooled size class
        first = a.data();
    }
    EXPECT_EQ(image_pool_bytes(), std::size_t(16) << 20);
    ImageF b(1024, 1024, 4, 0.0f);
    EXPECT_EQ(b.data(), first);  // the same buffer came back...
    EXPECT_EQ(image_pool_bytes(), 0u);
    for (std::size_t i = 0; i < b.num_values(); ++i)
        ASSERT_EQ(b.data()[i], 0.0f) << "value " << i;  // ...and was refilled
    ImageF c(b);  // copies are exact whatever buffer they get
    EXPECT_TRUE(c == b);
    {
        std::vector<ImageF> many;
        for (int i = 0; i < 20; ++i) many.emplace_back(1024, 1024, 4, kUninitialized);  // 320 MiB
    }
    EXPECT_LE(image_pool_bytes(), kImagePoolBytes);  // the oldest went back to the system
    EXPECT_GT(image_pool_bytes(), 0u);
    {
        ImageF small(16, 16, 1);  // small buffers never enter the pool
    }
    EXPECT_LE(image_pool_bytes(), kImagePoolBytes);
    image_pool_release();
    EXPECT_EQ(image_pool_bytes(), 0u);
}

// A one-shot render lowers the pool's limit (app/render_job.cpp): buffers beyond it go back to the
// system at once, and the previous limit comes back.
TEST(ImagePool, TheLimitCanBeLoweredAndRestored) {
    image_pool_release();
    const std::size_t before = set_image_pool_limit(std::size_t(8) << 20);
    EXPECT_EQ(before, kImagePoolBytes);
    {
        ImageF a(1024, 1024, 4, 1.0f);  // 16 MiB: more than the limit
    }
    EXPECT_EQ(image_pool_bytes(), 0u);
    {
        ImageF a(1024, 512, 4, 1.0f);  // 8 MiB: fits
    }
    EXPECT_EQ(image_pool_bytes(), std::size_t(8) << 20);
    EXPECT_EQ(set_image_pool_limit(before), std::size_t(8) << 20);
    image_pool_release();
}

}  // namespace
}  // namespace aq
