#include "ros_messages.h"

#include <boost/make_shared.hpp>
#include <cstring>

#include "deepsea/core/error.h"
#include "deepsea/io/config.h"
#include "deepsea/optics/snow.h"
#include "deepsea/runtime/marine_snow.h"

namespace deepsea::ros1 {

ImageMessage fields(const sensor_msgs::Image& msg, const char* topic) {
    ImageMessage m;
    m.encoding = msg.encoding;
    m.width = msg.width;
    m.height = msg.height;
    m.step = msg.step;
    m.big_endian = msg.is_bigendian != 0;
    m.data = msg.data.data();
    m.size = msg.data.size();
    m.topic = topic;
    return m;
}

sensor_msgs::ImagePtr image_message(const std_msgs::Header& header, int width, int height,
                                    const std::string& encoding, const void* bytes,
                                    std::size_t sample_bytes) {
    auto msg = boost::make_shared<sensor_msgs::Image>();
    msg->header = header;
    msg->width = std::uint32_t(width);
    msg->height = std::uint32_t(height);
    msg->encoding = encoding;
    msg->is_bigendian = 0;
    const std::size_t channels = encoding == "rgb8" ? 3 : 1;
    msg->step = std::uint32_t(std::size_t(width) * channels * sample_bytes);
    msg->data.resize(std::size_t(msg->step) * std::size_t(height));
    std::memcpy(msg->data.data(), bytes, msg->data.size());
    return msg;
}

sensor_msgs::CameraInfoPtr camera_info(const std_msgs::Header& header, const Camera& c) {
    auto info = boost::make_shared<sensor_msgs::CameraInfo>();
    info->header = header;
    info->width = std::uint32_t(c.width);
    info->height = std::uint32_t(c.height);
    info->distortion_model = "plumb_bob";
    info->D.assign(5, 0.0);
    info->K = {c.fx, 0.0, c.cx, 0.0, c.fy, c.cy, 0.0, 0.0, 1.0};
    info->R = {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0};
    info->P = {c.fx, 0.0, c.cx, 0.0, 0.0, c.fy, c.cy, 0.0, 0.0, 0.0, 1.0, 0.0};
    return info;
}

Camera camera_of(const sensor_msgs::CameraInfo& info) {
    return Camera{int(info.width), int(info.height), info.K[0], info.K[4], info.K[2], info.K[5]};
}

LiveSettings live_settings(const Options& o) {
    if (o.asset.empty()) throw ConfigError("asset: give the baked asset (.vdb) to render with");
    LiveSettings s;
    std::optional<Snow> setup_snow;
    if (!o.camera_yaml.empty()) {
        const Setup setup = load_setup({o.camera_yaml});
        if (setup.camera) s.render.camera = *setup.camera;
        s.camera_model = setup.camera_model;
        s.render.port = setup.port;
        setup_snow = setup.snow;
    }
    if (s.camera_model && o.exposure != "auto")
        throw ConfigError("exposure: " + o.camera_yaml +
                          " records the frames with a camera, whose exposure is "
                          "camera.sensor's exposure_time_ms and gain");
    s.exposure = parse_exposure(o.exposure);
    s.render.forward = o.forward;
    s.render.shadows = o.shadows;
    if (o.snow != "off" && (!o.snow.empty() || setup_snow)) {
        SnowSettings snow;
        snow.snow = o.snow.empty() ? *setup_snow : snow_preset(o.snow, "snow");
        snow.seed = std::uint64_t(o.snow_seed);
        const CameraModel m = s.camera_model ? *s.camera_model : CameraModel{};
        snow.f_number = m.lens.f_number;
        snow.pixel_pitch_um = m.sensor.pixel_pitch_um;
        snow.focus_distance_m = m.lens.focus_distance_m;
        validate(snow);
        s.render.snow = snow;
    }
    s.backscatter = o.backscatter;
    s.noise_free = o.noise_free;
    s.depth = o.depth;
    if (!(o.depth_scale > 0.0)) throw ConfigError("depth_scale: must be > 0 (metres per unit)");
    if (!(o.slop >= 0.0)) throw ConfigError("slop: must be >= 0 seconds");
    if (o.queue < 1) throw ConfigError("queue_size: must be >= 1");
    (void)pair_policy(o);
    return s;
}

PairPolicy pair_policy(const Options& o) {
    if (o.sync == "exact") return PairPolicy::Exact;
    if (o.sync == "approximate") return PairPolicy::Approximate;
    throw ConfigError("sync: '" + o.sync + "' is not exact or approximate");
}

}  // namespace deepsea::ros1
