// fuzz/fuzz_pipeline.cpp — bytes -> aq::stylize::parse_pipeline, then validate_pipeline (the
// style JSON of --style and of a scene file's "style"). parse_pipeline takes the text directly;
// the base folder is the fuzzer's scratch folder, where paper.png exists, so paper paths resolve
// the way a style file beside its paper does.
#include <cstdint>
#include <string>

#include "core/io.h"
#include "fuzz/fuzz_common.h"
#include "stylize/pipeline.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    aq::write_image(aq::fuzz::temp_dir() + "/paper.png", aq::ImageF(8, 8, 3, 0.5f));
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    aq::fuzz::expect_only_aq_errors("parse_pipeline/validate_pipeline", [&] {
        const aq::stylize::Pipeline p = aq::stylize::parse_pipeline(text, "fuzz.json", aq::fuzz::temp_dir());
        aq::stylize::validate_pipeline(p);
    });
    return 0;
}
