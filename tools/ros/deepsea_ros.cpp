// deepsea_ros: a ROS 1 node that turns a simulated RGB-D camera into a deep-sea camera
// (docs/ros.md). Thin: callbacks pair colour and depth (deepsea/live's StampPairer), check the
// messages, and leave the latest pair for the render thread (LatestSlot), which renders through
// LiveRenderer and publishes. A ROS 2 port replaces this file only.

#include <diagnostic_msgs/DiagnosticArray.h>
#include <ros/ros.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <mutex>
#include <thread>

#include "deepsea/asset/asset_file.h"
#include "deepsea/core/error.h"
#include "deepsea/live/latest_slot.h"
#include "ros_messages.h"

namespace deepsea::ros1 {
namespace {

using ImageConstPtr = sensor_msgs::ImageConstPtr;

struct Pair {
    ImageConstPtr color, depth;
    std::chrono::steady_clock::time_point paired;  ///< when the pair was complete
};

/// The counts the diagnostics message carries.
struct Counts {
    std::atomic<std::uint64_t> color{0}, depth{0}, malformed{0}, mismatched{0}, errors{0},
        rendered{0};
    std::mutex mutex;  // the times below
    double latency_last = 0, latency_sum = 0, latency_max = 0, render_sum = 0;
};

const char* const kColorTopic = "camera/image_raw";
const char* const kDepthTopic = "camera/depth/image_raw";

class Node {
public:
    Node(ros::NodeHandle& nh, ros::NodeHandle& pnh, const Options& o, const Asset& asset)
        : m_options(o),
          m_live(asset, live_settings(o)),
          m_pairer(pair_policy(o), std::int64_t(o.slop * 1e9), std::size_t(o.queue)) {
        m_image = nh.advertise<sensor_msgs::Image>("deepsea/image_raw", 2);
        m_info = nh.advertise<sensor_msgs::CameraInfo>("deepsea/camera_info", 2);
        if (o.backscatter) m_back = nh.advertise<sensor_msgs::Image>("deepsea/backscatter", 2);
        if (o.noise_free) m_clean = nh.advertise<sensor_msgs::Image>("deepsea/noise_free", 2);
        if (o.depth) m_depth = nh.advertise<sensor_msgs::Image>("deepsea/depth", 2);
        m_diag = nh.advertise<diagnostic_msgs::DiagnosticArray>("/diagnostics", 4);
        const ros::TransportHints hints = ros::TransportHints().tcpNoDelay();
        m_color_sub = nh.subscribe(kColorTopic, 4, &Node::on_color, this, hints);
        m_depth_sub = nh.subscribe(kDepthTopic, 4, &Node::on_depth, this, hints);
        m_info_sub = nh.subscribe("camera/camera_info", 2, &Node::on_info, this, hints);
        m_color_name = m_color_sub.getTopic();  // resolved: what errors name
        m_depth_name = m_depth_sub.getTopic();
        double period = 1.0;
        pnh.param("diagnostics_period", period, 1.0);
        m_timer = nh.createWallTimer(ros::WallDuration(std::max(period, 0.05)),
                                     [this](const ros::WallTimerEvent&) { publish_diagnostics(); });
        m_thread = std::thread([this] { render_loop(); });
    }

    ~Node() {
        m_slot.close();
        if (m_thread.joinable()) m_thread.join();
    }

private:
    void on_color(const ImageConstPtr& msg) {
        ++m_counts.color;
        std::lock_guard<std::mutex> lock(m_pair_mutex);
        if (auto p = m_pairer.add_color(msg->header.stamp.toNSec(), msg)) offer(*p);
    }
    void on_depth(const ImageConstPtr& msg) {
        ++m_counts.depth;
        std::lock_guard<std::mutex> lock(m_pair_mutex);
        if (auto p = m_pairer.add_depth(msg->header.stamp.toNSec(), msg)) offer(*p);
    }
    void on_info(const sensor_msgs::CameraInfoConstPtr& msg) {
        std::lock_guard<std::mutex> lock(m_info_mutex);
        m_last_info = msg;
    }

    /// A pair whose messages pass the checks goes to the render thread (replacing a waiting
    /// one); a malformed one is counted and reported once per change of reason.
    void offer(const std::pair<ImageConstPtr, ImageConstPtr>& p) {
        try {
            check_same_size(
                color_view(fields(*p.first, m_color_name.c_str())),
                depth_view(fields(*p.second, m_depth_name.c_str()), m_options.depth_scale));
            m_malformed_report.report("");
        } catch (const Error& e) {
            ++m_counts.malformed;
            if (m_malformed_report.report(e.what()))
                ROS_WARN("deepsea_ros: skipping malformed frame: %s", e.what());
            return;
        }
        m_slot.put(Pair{p.first, p.second, std::chrono::steady_clock::now()});
    }

    void render_loop() {
        LiveFrame out;
        while (auto pair = m_slot.take()) {
            const auto start = std::chrono::steady_clock::now();
            const sensor_msgs::Image& c = *pair->color;
            try {
                m_live.render(
                    out, color_view(fields(c, m_color_name.c_str())),
                    depth_view(fields(*pair->depth, m_depth_name.c_str()), m_options.depth_scale),
                    c.header.stamp.toNSec());
                m_sizes = m_live.sizes_seen();
                m_exposure = m_live.exposure();
                m_render_report.report("");
            } catch (const AssetError& e) {
                ++m_counts.mismatched;
                if (m_render_report.report(e.what())) ROS_ERROR("deepsea_ros: %s", e.what());
                continue;
            } catch (const std::exception& e) {
                ++m_counts.errors;
                if (m_render_report.report(e.what())) ROS_ERROR("deepsea_ros: %s", e.what());
                continue;
            }
            check_intrinsics(out.camera);
            publish(c.header, out);
            const auto end = std::chrono::steady_clock::now();
            const double latency =
                std::chrono::duration<double, std::milli>(end - pair->paired).count();
            const double render = std::chrono::duration<double, std::milli>(end - start).count();
            ++m_counts.rendered;
            std::lock_guard<std::mutex> lock(m_counts.mutex);
            m_counts.latency_last = latency;
            m_counts.latency_sum += latency;
            m_counts.latency_max = std::max(m_counts.latency_max, latency);
            m_counts.render_sum += render;
        }
    }

    /// The simulator's camera_info against the camera the frames are rendered for: an error
    /// once per change (the backscatter was baked for another camera).
    void check_intrinsics(const Camera& cam) {
        sensor_msgs::CameraInfoConstPtr info;
        {
            std::lock_guard<std::mutex> lock(m_info_mutex);
            info = m_last_info;
        }
        if (!info) return;
        const std::string e = intrinsics_mismatch(cam, camera_of(*info));
        if (!e.empty()) ++m_counts.mismatched;
        if (m_info_report.report(e)) ROS_ERROR("deepsea_ros: %s", e.c_str());
    }

    void publish(const std_msgs::Header& h, const LiveFrame& f) {
        m_info.publish(camera_info(h, f.camera));
        m_image.publish(image_message(h, f.width, f.height, "rgb8", f.image.data(), 1));
        if (m_options.backscatter)
            m_back.publish(image_message(h, f.width, f.height, "rgb8", f.backscatter.data(), 1));
        if (m_options.noise_free)
            m_clean.publish(image_message(h, f.width, f.height, "rgb8", f.noise_free.data(), 1));
        if (m_options.depth)
            m_depth.publish(image_message(h, f.width, f.height, "32FC1", f.depth.data(), 4));
    }

    void publish_diagnostics() {
        diagnostic_msgs::DiagnosticArray a;
        a.header.stamp = ros::Time::now();
        diagnostic_msgs::DiagnosticStatus s;
        s.name = ros::this_node::getName() + ": deep-sea camera";
        s.hardware_id = m_options.asset;
        const std::uint64_t rendered = m_counts.rendered, bad = m_counts.malformed,
                            mismatched = m_counts.mismatched;
        s.level = mismatched > 0 || m_counts.errors > 0 ? diagnostic_msgs::DiagnosticStatus::ERROR
                  : bad > 0                             ? diagnostic_msgs::DiagnosticStatus::WARN
                                                        : diagnostic_msgs::DiagnosticStatus::OK;
        s.message = std::to_string(rendered) + " frame(s) rendered";
        const auto kv = [&](const char* k, const std::string& v) {
            diagnostic_msgs::KeyValue x;
            x.key = k;
            x.value = v;
            s.values.push_back(x);
        };
        std::uint64_t unpaired = 0;
        {
            std::lock_guard<std::mutex> lock(m_pair_mutex);
            unpaired = m_pairer.unpaired();
        }
        kv("colour_received", std::to_string(m_counts.color.load()));
        kv("depth_received", std::to_string(m_counts.depth.load()));
        kv("unpaired", std::to_string(unpaired));
        kv("dropped", std::to_string(m_slot.replaced()));
        kv("malformed", std::to_string(bad));
        kv("mismatched", std::to_string(mismatched));
        kv("render_errors", std::to_string(m_counts.errors.load()));
        kv("rendered", std::to_string(rendered));
        kv("sizes_seen", std::to_string(m_sizes.load()));
        kv("exposure", std::to_string(m_exposure.load()));
        {
            std::lock_guard<std::mutex> lock(m_counts.mutex);
            const double n = double(std::max<std::uint64_t>(rendered, 1));
            kv("latency_ms_last", std::to_string(m_counts.latency_last));
            kv("latency_ms_mean", std::to_string(m_counts.latency_sum / n));
            kv("latency_ms_max", std::to_string(m_counts.latency_max));
            kv("render_ms_mean", std::to_string(m_counts.render_sum / n));
        }
        a.status.push_back(s);
        m_diag.publish(a);
    }

    Options m_options;
    LiveRenderer m_live;  // the render thread's only
    std::string m_color_name, m_depth_name;
    std::atomic<int> m_sizes{0};  // the renderer's, for the diagnostics timer
    std::atomic<double> m_exposure{0.0};
    std::mutex m_pair_mutex;
    StampPairer<ImageConstPtr, ImageConstPtr> m_pairer;
    LatestSlot<Pair> m_slot;
    ChangeReporter m_malformed_report, m_render_report, m_info_report;
    std::mutex m_info_mutex;
    sensor_msgs::CameraInfoConstPtr m_last_info;
    Counts m_counts;
    ros::Publisher m_image, m_info, m_back, m_clean, m_depth, m_diag;
    ros::Subscriber m_color_sub, m_depth_sub, m_info_sub;
    ros::WallTimer m_timer;
    std::thread m_thread;
};

Options read_params(ros::NodeHandle& pnh) {
    Options o;
    pnh.getParam("asset", o.asset);
    pnh.getParam("camera_yaml", o.camera_yaml);
    // exposure: "auto" or a number (a YAML number arrives as a double)
    double factor = 0.0;
    if (pnh.getParam("exposure", factor))
        o.exposure = std::to_string(factor);
    else
        pnh.getParam("exposure", o.exposure);
    pnh.getParam("forward", o.forward);
    pnh.getParam("shadows", o.shadows);
    pnh.getParam("snow", o.snow);
    pnh.getParam("snow_seed", o.snow_seed);
    pnh.getParam("publish_backscatter", o.backscatter);
    pnh.getParam("publish_noise_free", o.noise_free);
    pnh.getParam("publish_depth", o.depth);
    pnh.getParam("depth_scale", o.depth_scale);
    pnh.getParam("sync", o.sync);
    pnh.getParam("slop", o.slop);
    pnh.getParam("queue_size", o.queue);
    return o;
}

}  // namespace
}  // namespace deepsea::ros1

int main(int argc, char** argv) {
    ros::init(argc, argv, "deepsea_ros");
    ros::NodeHandle nh, pnh("~");
    const deepsea::ros1::Options o = deepsea::ros1::read_params(pnh);
    try {
        const deepsea::Asset asset = deepsea::load_asset(o.asset);
        deepsea::ros1::Node node(nh, pnh, o, asset);
        ROS_INFO("deepsea_ros: rendering %s with %s",
                 nh.resolveName(deepsea::ros1::kColorTopic).c_str(), o.asset.c_str());
        ros::spin();
    } catch (const deepsea::Error& e) {
        std::fprintf(stderr, "deepsea_ros: error: %s\n", e.what());
        return e.exit_code();
    }
    return 0;
}
