// core/build_info.h — what built this binary: version, git commit (and whether the tracked files
// differed from it), compiler and the flags that decide the output bytes. Recorded in every
// provenance manifest (app/manifest.h, docs/provenance.md).
#pragma once

#include <string>

namespace aq {

struct BuildInfo {
    std::string version;      //!< project version (CMakeLists.txt), e.g. "0.1.0"
    std::string commit;       //!< full git commit hash at build time, or "unknown" outside a checkout
    bool dirty = false;       //!< tracked files differed from the commit when it was built
    std::string compiler;     //!< e.g. "GNU 12.2.0"
    std::string build_type;   //!< CMAKE_BUILD_TYPE
    std::string flags;        //!< the determinism flags and ISA options every target is compiled with
    //! "0.1.0 (commit abc123..., dirty)" for messages.
    std::string describe() const;
};

const BuildInfo& build_info();

}  // namespace aq
