// tests/test_support.h — paths to shared assets and a place for failure artefacts.
#pragma once

#include <string>

namespace aq::test {

//! ../shared next to the checkout ($AQ_SHARED overrides). Fails the test loudly if missing.
std::string shared_dir();
//! Path under shared/assets; ADD_FAILURE()s (and returns it anyway) if the file is missing.
std::string asset(const std::string& rel);
//! Folder for images written on failure (created on demand).
std::string output_dir();
//! Source tree root (for scenes/data, stylize/presets, ...).
std::string source_dir();

}  // namespace aq::test
