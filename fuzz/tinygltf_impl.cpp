// fuzz/tinygltf_impl.cpp — tinygltf 2.7.0's implementation, compiled from the system header with
// the fuzz build's coverage and sanitizer flags (fuzz/CMakeLists.txt, AQ_FUZZ_INSTRUMENT_TINYGLTF).
// The loader installs its own image loader and file-system callbacks, so stb_image (not packaged
// with Debian's header) is left out; the default image callbacks that the header's TinyGLTF class
// names in every translation unit are defined below as refusals (the loader never calls them).
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#include <tiny_gltf.h>

namespace tinygltf {

bool LoadImageData(Image*, const int, std::string* err, std::string*, int, int, const unsigned char*, int,
                   void*) {
    if (err) *err += "fuzz build: tinygltf's default image loader is not available\n";
    return false;
}

bool WriteImageData(const std::string*, const std::string*, const Image*, bool, std::string*, void*) {
    return false;
}

}  // namespace tinygltf
