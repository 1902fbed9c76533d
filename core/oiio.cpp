// core/oiio.cpp — see oiio.h.
#include "core/oiio.h"

#include <dlfcn.h>

#include <atomic>
#include <cstdlib>
#include <mutex>
#include <string>
#include <thread>

#include "core/image.h"

#ifndef AQ_OIIO_MODULE_PATH
#error "AQ_OIIO_MODULE_PATH must name the built libaq_oiio.so (core/CMakeLists.txt)"
#endif

namespace aq {
namespace {

struct Loader {
    std::mutex mu;  //!< held for the whole load: a second caller waits for the first
    std::atomic<const oiio_module::Api*> api{nullptr};
    std::thread preload;
    bool preload_started = false;  //!< under mu
    ~Loader() {
        // At exit, a preload still inside dlopen() is waited for rather than torn down under it.
        if (preload.joinable()) preload.join();
    }
};

Loader& loader() {
    static Loader l;
    return l;
}

std::string module_path() {
    if (const char* p = std::getenv("AQ_OIIO_MODULE"); p && *p) return p;
    return AQ_OIIO_MODULE_PATH;
}

//! Loads the module (caller holds l.mu). Returns "" or why it failed.
std::string load_locked(Loader& l) {
    if (l.api.load(std::memory_order_acquire)) return {};
    const std::string path = module_path();
    // RTLD_LAZY: the module's libraries bind their functions on first call, as they did when the
    // executable linked OpenImageIO directly. RTLD_LOCAL: nothing of it joins the global scope.
    void* h = ::dlopen(path.c_str(), RTLD_LAZY | RTLD_LOCAL);
    if (!h) {
        const char* e = ::dlerror();
        return "cannot load the OpenImageIO module '" + path + "': " + (e ? e : "unknown error") +
               " (build it: ninja -C build aq_oiio; or set AQ_OIIO_MODULE to its path)";
    }
    using Entry = const oiio_module::Api* (*)();
    const auto entry = reinterpret_cast<Entry>(::dlsym(h, "aq_oiio_module_api"));
    const oiio_module::Api* api = entry ? entry() : nullptr;
    if (!api || api->abi != oiio_module::kOiioModuleAbi) {
        ::dlclose(h);
        return "the OpenImageIO module '" + path + "' is not this build's (rebuild: ninja -C build aq_oiio)";
    }
    // Never unloaded: OpenImageIO keeps process-wide state (plugins, caches) until exit.
    l.api.store(api, std::memory_order_release);
    return {};
}

}  // namespace

const oiio_module::Api& oiio() {
    Loader& l = loader();
    if (const oiio_module::Api* api = l.api.load(std::memory_order_acquire)) return *api;
    std::lock_guard<std::mutex> lock(l.mu);
    if (const std::string e = load_locked(l); !e.empty()) throw Error(e);
    return *l.api.load(std::memory_order_acquire);
}

void preload_oiio() {
    Loader& l = loader();
    if (l.api.load(std::memory_order_acquire)) return;
    std::lock_guard<std::mutex> lock(l.mu);
    if (l.preload_started) return;
    l.preload_started = true;
    l.preload = std::thread([&l] {
        std::lock_guard<std::mutex> inner(l.mu);
        (void)load_locked(l);  // a failure is reported by the oiio() call that needs the module
    });
}

bool oiio_loaded() { return loader().api.load(std::memory_order_acquire) != nullptr; }

}  // namespace aq
