// core/build_info.cpp — see build_info.h. AQ_VERSION, AQ_COMPILER, AQ_BUILD_TYPE and AQ_FLAGS come
// from core/CMakeLists.txt; the commit from the header cmake/build_info.cmake writes at build time.
#include "core/build_info.h"

#include "aq_build_info.h"

namespace aq {

std::string BuildInfo::describe() const {
    return version + " (commit " + commit + (dirty ? ", with uncommitted changes" : "") + ")";
}

const BuildInfo& build_info() {
    static const BuildInfo info{AQ_VERSION, AQ_GIT_COMMIT, AQ_GIT_DIRTY != 0, AQ_COMPILER, AQ_BUILD_TYPE, AQ_FLAGS};
    return info;
}

}  // namespace aq
