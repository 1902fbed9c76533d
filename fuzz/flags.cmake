# fuzz/flags.cmake — included by the top-level CMakeLists.txt when AQ_BUILD_FUZZ is ON, before any
# library is defined: the whole build is compiled with coverage instrumentation for libFuzzer and
# with AddressSanitizer + UndefinedBehaviorSanitizer, so a finding inside aq_core / aq_scenes /
# aq_stylize is reported where it happens. Use a separate build folder (scripts/fuzz.sh: build-fuzz).
if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
  message(WARNING "AQ_BUILD_FUZZ needs clang (libFuzzer); compiler is ${CMAKE_CXX_COMPILER_ID}: "
                  "fuzz targets are not built. Configure with CC=clang CXX=clang++ (scripts/fuzz.sh).")
  set(AQ_BUILD_FUZZ OFF)
  return()
endif()
set(AQ_FUZZ_SANITIZERS -fsanitize=address,undefined -fno-sanitize-recover=undefined)
add_compile_options(-fsanitize=fuzzer-no-link ${AQ_FUZZ_SANITIZERS} -fno-omit-frame-pointer -g)
add_link_options(${AQ_FUZZ_SANITIZERS})
