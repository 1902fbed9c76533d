// fuzz/fuzz_live_message.cpp — bytes -> aq::app::parse_live_message: every WebSocket message a
// page of `aquarelle serve` may send is parsed by it before anything else sees it (app/serve.h).
// Only aq::Error may come out; a message it accepts yields render arguments of bounded size.
#include <cstdint>
#include <string>

#include "app/serve.h"
#include "fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    aq::fuzz::expect_only_aq_errors("parse_live_message", [&] {
        const aq::app::LiveRequest r = aq::app::parse_live_message(text);
        std::size_t bytes = 0;
        for (const std::string& a : r.args) bytes += a.size();
        if (bytes > 2 * text.size() + 64) __builtin_trap();  // arguments never outgrow the message
    });
    return 0;
}
