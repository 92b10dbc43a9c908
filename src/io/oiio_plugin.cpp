// libdeepsea_oiio.so: the OpenImageIO calls of image_oiio.cpp, loaded on first use (see
// oiio_plugin.h for why). Only OpenImageIO and the standard library: no deepsea code.
//
// Errors are taken per call with OpenImageIO's geterror() (the global one where no reader or
// writer exists yet), which also clears them: every call leaves none pending, so a later call
// never reports an earlier one's.

#include "oiio_plugin.h"

#include <OpenImageIO/imageio.h>

#include <cerrno>
#include <cstring>
#include <memory>

namespace {

using deepsea::io_detail::OiioHeader;
using deepsea::io_detail::OiioPixel;
using deepsea::io_detail::OiioPlugin;
using deepsea::io_detail::OiioWriteSpec;
using deepsea::io_detail::OiioWritten;

OiioPixel pixel_of(OIIO::TypeDesc t) {
    switch (t.basetype) {
        case OIIO::TypeDesc::UINT8:
            return OiioPixel::UInt8;
        case OIIO::TypeDesc::UINT16:
            return OiioPixel::UInt16;
        case OIIO::TypeDesc::HALF:
            return OiioPixel::Half;
        case OIIO::TypeDesc::FLOAT:
            return OiioPixel::Float;
        case OIIO::TypeDesc::DOUBLE:
            return OiioPixel::Double;
        default:
            return OiioPixel::Other;
    }
}

OIIO::TypeDesc type_of(OiioPixel p) {
    switch (p) {
        case OiioPixel::UInt8:
            return OIIO::TypeDesc::UINT8;
        case OiioPixel::UInt16:
            return OIIO::TypeDesc::UINT16;
        case OiioPixel::Half:
            return OIIO::TypeDesc::HALF;
        case OiioPixel::Double:
            return OIIO::TypeDesc::DOUBLE;
        default:
            return OIIO::TypeDesc::FLOAT;
    }
}

void* open(const std::string& path, OiioHeader& header, std::string& error) {
    // Keep colour unassociated: OIIO would otherwise premultiply RGBA PNG/TIFF by alpha, and
    // alpha is dropped by deepsea, not composited.
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto in = OIIO::ImageInput::open(path, &config);
    if (!in) {
        error = OIIO::geterror();
        return nullptr;
    }
    (void)OIIO::geterror();  // what the readers tried before this one's format said
    const OIIO::ImageSpec& spec = in->spec();
    header.width = spec.width;
    header.height = spec.height;
    header.channels = spec.nchannels;
    header.depth = spec.depth;
    header.pixel = pixel_of(spec.format);
    header.pixel_name = spec.format.c_str();
    header.format_name = in->format_name();
    header.channel_names = spec.channelnames;
    return in.release();
}

bool read(void* input, int begin, int end, bool as_uint16, void* out, std::string& error) {
    auto* in = static_cast<OIIO::ImageInput*>(input);
    const bool ok = in->read_image(0, 0, begin, end,
                                   as_uint16 ? OIIO::TypeDesc::UINT16 : OIIO::TypeDesc::FLOAT, out);
    error = in->geterror();  // cleared also when the read succeeded
    return ok;
}

void close(void* input) {
    std::unique_ptr<OIIO::ImageInput> in(static_cast<OIIO::ImageInput*>(input));
    in->close();
    (void)in->geterror();
}

bool has_writer(const std::string& path) {
    const bool ok = OIIO::ImageOutput::create(path) != nullptr;
    if (!ok) (void)OIIO::geterror();  // clear it: a later error must not carry this one
    return ok;
}

OiioWritten write(const std::string& path, const OiioWriteSpec& w, const float* data,
                  std::string& error) {
    auto out = OIIO::ImageOutput::create(path);
    if (!out) {
        (void)OIIO::geterror();
        return OiioWritten::NoWriter;
    }
    OIIO::ImageSpec spec(w.width, w.height, w.channels, type_of(w.pixel));
    if (!w.channel_names.empty()) spec.channelnames = w.channel_names;
    for (const auto& [name, value] : w.attributes) spec.attribute(name, value);
    if (!out->open(path, spec)) {
        error = out->geterror();
        return OiioWritten::Failed;
    }
    errno = 0;
    bool ok = out->write_image(OIIO::TypeDesc::FLOAT, data);
    ok = out->close() && ok;
    error = out->geterror();
    if (ok) return OiioWritten::Written;
    if (errno != 0) error += std::string(" (") + std::strerror(errno) + ")";
    return OiioWritten::Failed;
}

const OiioPlugin kPlugin{deepsea::io_detail::kOiioPluginAbi, open, read, close, has_writer, write};

}  // namespace

extern "C" __attribute__((visibility("default"))) const OiioPlugin* deepsea_oiio_plugin() {
    return &kPlugin;
}
