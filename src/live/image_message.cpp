#include "deepsea/live/image_message.h"

#include <string>

#include "deepsea/core/error.h"

namespace deepsea {

namespace {

struct Layout {
    SampleType type;
    int samples;  ///< per pixel
    ChannelOrder order;
};

bool color_layout(const std::string& e, Layout& out) {
    if (e == "rgb8")
        out = {SampleType::U8, 3, ChannelOrder::Rgb};
    else if (e == "bgr8")
        out = {SampleType::U8, 3, ChannelOrder::Bgr};
    else if (e == "rgba8")
        out = {SampleType::U8, 4, ChannelOrder::Rgb};
    else if (e == "bgra8")
        out = {SampleType::U8, 4, ChannelOrder::Bgr};
    else if (e == "rgb16")
        out = {SampleType::U16, 3, ChannelOrder::Rgb};
    else if (e == "bgr16")
        out = {SampleType::U16, 3, ChannelOrder::Bgr};
    else if (e == "rgba16")
        out = {SampleType::U16, 4, ChannelOrder::Rgb};
    else
        return false;
    return true;
}

[[noreturn]] void refuse(const ImageMessage& m, const std::string& why) {
    throw InputError(std::string(m.topic) + ": " + why);
}

/// The checks every image shares: a size, data, rows that fit, byte order.
void check_buffer(const ImageMessage& m, std::size_t pixel_bytes, std::size_t sample) {
    if (m.width == 0 || m.height == 0 || m.data == nullptr || m.size == 0)
        refuse(m, "empty image (" + std::to_string(m.width) + "x" + std::to_string(m.height) +
                      ", " + std::to_string(m.size) + " bytes of data)");
    const std::size_t row = std::size_t(m.width) * pixel_bytes;
    if (m.step < row)
        refuse(m, "step " + std::to_string(m.step) + " is shorter than a row of " +
                      std::to_string(m.width) + " " + m.encoding + " pixels (" +
                      std::to_string(row) + " bytes)");
    if (m.step % sample != 0)
        refuse(m, "step " + std::to_string(m.step) + " is not a whole number of " +
                      std::to_string(sample) + "-byte samples");
    const std::size_t need = std::size_t(m.step) * m.height;
    if (m.size != need)
        refuse(m, "data holds " + std::to_string(m.size) + " bytes, step x height is " +
                      std::to_string(need));
    if (m.big_endian && sample > 1)
        refuse(m, "big-endian " + m.encoding + " samples (is_bigendian) on a little-endian host");
}

}  // namespace

ColorView color_view(const ImageMessage& m) {
    Layout l{};
    if (!color_layout(m.encoding, l))
        refuse(m, "encoding '" + m.encoding +
                      "' is not a colour encoding deepsea takes (rgb8, bgr8, rgba8, bgra8, "
                      "rgb16, bgr16, rgba16)");
    const std::size_t sample = sample_bytes(l.type);
    check_buffer(m, sample * l.samples, sample);
    ColorView v;
    v.data = m.data;
    v.width = int(m.width);
    v.height = int(m.height);
    v.type = l.type;
    v.encoding = ColorEncoding::Srgb;
    v.order = l.order;
    v.pixel_stride = std::ptrdiff_t(sample * l.samples);
    v.row_stride = std::ptrdiff_t(m.step);
    v.name = m.topic;
    return checked(v, m.topic);
}

DepthView depth_view(const ImageMessage& m, double mm_scale) {
    SampleType type;
    if (m.encoding == "32FC1")
        type = SampleType::F32;
    else if (m.encoding == "16UC1" || m.encoding == "mono16")
        type = SampleType::U16;
    else
        refuse(m, "encoding '" + m.encoding +
                      "' is not a depth encoding deepsea takes (32FC1 metres, 16UC1 "
                      "millimetres; REP 118)");
    const std::size_t sample = sample_bytes(type);
    check_buffer(m, sample, sample);
    DepthView v;
    v.data = m.data;
    v.width = int(m.width);
    v.height = int(m.height);
    v.type = type;
    v.kind = DepthKind::Z;
    v.scale = mm_scale;
    v.pixel_stride = std::ptrdiff_t(sample);
    v.row_stride = std::ptrdiff_t(m.step);
    v.name = m.topic;
    return checked(v, m.topic);
}

void check_same_size(const ColorView& color, const DepthView& depth) {
    if (color.width == depth.width && color.height == depth.height) return;
    const auto size = [](int w, int h) { return std::to_string(w) + "x" + std::to_string(h); };
    throw InputError(
        std::string(color.name ? color.name : "colour") + " is " + size(color.width, color.height) +
        " but " + (depth.name ? depth.name : "depth") + " is " + size(depth.width, depth.height));
}

}  // namespace deepsea
