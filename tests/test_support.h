// tests/test_support.h — paths to shared assets and each test's own output folder; the message of
// an expected aq::Error.
#pragma once

#include <functional>
#include <string>

namespace aq::test {

//! ../shared next to the checkout ($AQ_SHARED overrides). Fails the test loudly if missing.
std::string shared_dir();
//! Path under shared/assets; ADD_FAILURE()s (and returns it anyway) if the file is missing.
std::string asset(const std::string& rel);
//! This test process's own folder for every file a test writes (inputs it builds, outputs, failure
//! artefacts): `<build>/test-output/<Suite.Test>.XXXXXX`, made unique with mkdtemp on first use.
//! CTest runs each test in its own process, possibly in parallel, so no two tests share a folder.
//! The folder is removed when every test of the process passed and kept (its path printed) when
//! one failed, so failure images can be inspected.
std::string output_dir();
//! Source tree root (for scenes/data, stylize/presets, ...).
std::string source_dir();
//! The message of the aq::Error that f throws, or "(no error)".
std::string error_of(const std::function<void()>& f);

//! `s` quoted for /bin/sh (single quotes).
std::string shell_quote(const std::string& s);
//! Runs a /bin/sh command line; returns its exit status (0-255, or -1 when it did not exit), and its
//! stdout and stderr together in *output when given.
int run_command(const std::string& command, std::string* output = nullptr);
//! The whole content of a file ("" when it cannot be read).
std::string file_bytes(const std::string& path);

}  // namespace aq::test
