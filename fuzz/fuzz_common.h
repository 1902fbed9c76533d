// fuzz/fuzz_common.h — helpers shared by the libFuzzer targets (fuzz/README.md).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace aq::fuzz {

//! Decoded image bytes a fuzz input may cost (images, glTF textures, scene-file images): 64 MiB,
//! not the product's 1 GiB (scenes/scene.h kMaxDecodedBytesPerRender). An image within every
//! limit may decode to hundreds of megabytes, seconds under ASan: long enough on a slow machine
//! for libFuzzer's slow-unit report (fuzz/README.md finding 10). Same check, smaller amount.
inline constexpr std::size_t kDecodeBytes = std::size_t(64) << 20;

//! This process's scratch folder, made once with mkdtemp under $TMPDIR (else /tmp) and removed at
//! normal exit. A crashing process leaves it behind; scripts/fuzz.sh points TMPDIR at its own
//! temporary folder and removes that, so nothing is left in /tmp or in the repository.
const std::string& temp_dir();

//! Writes bytes to temp_dir()/name (replacing it) and returns the full path. Aborts on I/O errors:
//! a fuzzer that cannot write its input must not report rejections as if they were findings.
std::string write_temp(const std::string& name, const std::uint8_t* data, std::size_t size);

//! Runs fn(); an aq::Error is the expected rejection of a hostile input. Any other exception
//! escaping a reader breaks the API contract (every reader documents aq::Error only), so it is
//! reported with its type and message and turned into a crash for libFuzzer to record.
template <class Fn>
void expect_only_aq_errors(const char* what, Fn&& fn);

[[noreturn]] void unexpected_exception(const char* what, const char* type, const char* msg);

//! AQ_FUZZ_VERBOSE=1 prints every rejection and acceptance (to check what seeds reach).
bool verbose();
void report(const char* what, const char* outcome);

}  // namespace aq::fuzz

#include <exception>
#include <new>
#include <typeinfo>

#include "core/image.h"  // aq::Error

template <class Fn>
void aq::fuzz::expect_only_aq_errors(const char* what, Fn&& fn) {
    try {
        fn();
        if (verbose()) report(what, "accepted");
    } catch (const aq::Error& e) {
        // Expected: the reader refused the input with a message.
        if (verbose()) report(what, e.what());
    } catch (const std::exception& e) {
        unexpected_exception(what, typeid(e).name(), e.what());
    } catch (...) {
        unexpected_exception(what, "(not a std::exception)", "");
    }
}
