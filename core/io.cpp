// core/io.cpp — OpenImageIO read/write with atomic rename.
#include "core/io.h"

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <vector>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

namespace aq {
namespace fs = std::filesystem;

void ensure_directory(const std::string& dir) {
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec || !fs::is_directory(dir))
        throw Error("cannot create folder '" + dir + "': " + (ec ? ec.message() : "not a folder"));
}

std::string safe_file_name(const std::string& name) {
    std::string s = name;
    for (char& c : s)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-')) c = '_';
    return s;
}

void write_image(const std::string& path, const ImageF& img) {
    if (img.empty()) throw Error("write '" + path + "': the image is empty");
    const fs::path dst(path);
    std::string ext = dst.extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    const bool eight_bit = (ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".bmp");
    if (ext.empty()) throw Error("write '" + path + "': no file extension to choose a format");

    OIIO::ImageSpec spec(img.width(), img.height(), img.channels(),
                         eight_bit ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT);
    if (ext == ".exr") {
        spec.attribute("compression", "zip");
        // OpenImageIO stamps EXR files with the wall-clock time (capDate) unless DateTime is set;
        // a fixed value keeps "same input, same bytes" true for whole files, not only pixels.
        spec.attribute("DateTime", "1970:01:01 00:00:00");
    }

    // Temporary file beside the destination, same extension so OIIO picks the same format.
    const fs::path dir = dst.has_parent_path() ? dst.parent_path() : fs::path(".");
    if (!fs::is_directory(dir)) throw Error("write '" + path + "': folder '" + dir.string() + "' does not exist");
    const fs::path tmp = dir / ("." + dst.stem().string() + ".tmp" + std::to_string(::getpid()) + ext);

    auto out = OIIO::ImageOutput::create(tmp.string());
    if (!out) throw Error("write '" + path + "': no writer for '" + ext + "': " + OIIO::geterror());
    if (!out->open(tmp.string(), spec)) {
        std::string e = out->geterror();
        throw Error("write '" + path + "': " + e);
    }
    bool ok;
    if (eight_bit) {
        std::vector<unsigned char> q(img.num_values());
        const float* p = img.data();
        for (std::size_t i = 0; i < q.size(); ++i) {
            float v = p[i];
            v = std::isnan(v) ? 0.0f : std::clamp(v, 0.0f, 1.0f);
            q[i] = static_cast<unsigned char>(std::lround(v * 255.0f));
        }
        ok = out->write_image(OIIO::TypeDesc::UINT8, q.data());
    } else {
        ok = out->write_image(OIIO::TypeDesc::FLOAT, img.data());
    }
    std::string err = ok ? "" : out->geterror();
    ok = out->close() && ok;
    if (!ok) {
        std::error_code ec;
        fs::remove(tmp, ec);
        throw Error("write '" + path + "': " + (err.empty() ? std::string("close failed") : err));
    }
    std::error_code ec;
    fs::rename(tmp, dst, ec);
    if (ec) {
        fs::remove(tmp, ec);
        throw Error("write '" + path + "': cannot rename the finished file into place");
    }
}

ImageF read_image(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw Error("read '" + path + "': " + OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    check_image_size(spec.width, spec.height, "read '" + path + "'");
    const int c = std::min(spec.nchannels, 4);
    ImageF img(spec.width, spec.height, c);
    if (!in->read_image(0, 0, 0, c, OIIO::TypeDesc::FLOAT, img.data())) {
        std::string e = in->geterror();
        throw Error("read '" + path + "': " + e);
    }
    return img;
}

}  // namespace aq
