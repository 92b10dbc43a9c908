// deepsea_rosbag: a recorded bag's RGB-D topics to a new bag with the deep-sea images
// (docs/ros.md, "Offline"). The same core as deepsea_ros (pairing, checks, LiveRenderer), in
// bag order, every pair rendered (no frame dropped): the new bag holds every message of the
// old one plus the rendered topics, stamped as their colour frames. Written to a temporary
// beside the output and renamed.

#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <CLI/CLI.hpp>
#include <cstdio>

#include "deepsea/asset/asset_file.h"
#include "deepsea/core/atomic_file.h"
#include "deepsea/core/error.h"
#include "ros_messages.h"

namespace deepsea::ros1 {
namespace {

struct Args {
    Options o;
    std::string in, out, color = "/camera/image_raw", depth = "/camera/depth/image_raw";
    std::string prefix = "/deepsea";
};

struct Totals {
    long pairs = 0, rendered = 0, malformed = 0, failed = 0;
};

void convert(const Args& a, const Asset& asset, const std::string& tmp, Totals& t) {
    LiveRenderer live(asset, live_settings(a.o));
    StampPairer<sensor_msgs::ImageConstPtr, sensor_msgs::ImageConstPtr> pairer(
        pair_policy(a.o), std::int64_t(a.o.slop * 1e9), std::size_t(a.o.queue));
    rosbag::Bag in;
    in.open(a.in, rosbag::bagmode::Read);
    rosbag::Bag out;
    out.open(tmp, rosbag::bagmode::Write);
    LiveFrame f;
    std::string last_error;
    const auto render = [&](const sensor_msgs::ImageConstPtr& c,
                            const sensor_msgs::ImageConstPtr& d) {
        ++t.pairs;
        try {
            const ImageMessage cm = fields(*c, a.color.c_str()), dm = fields(*d, a.depth.c_str());
            const ColorView cv = color_view(cm);
            const DepthView dv = depth_view(dm, a.o.depth_scale);
            check_same_size(cv, dv);
            live.render(f, cv, dv, c->header.stamp.toNSec());
        } catch (const InputError& e) {
            ++t.malformed;
            if (e.what() != last_error)
                std::fprintf(stderr, "deepsea_rosbag: skipped: %s\n", e.what());
            last_error = e.what();
            return;
        }
        const ros::Time when = c->header.stamp;
        out.write(a.prefix + "/image_raw", when,
                  image_message(c->header, f.width, f.height, "rgb8", f.image.data(), 1));
        out.write(a.prefix + "/camera_info", when, camera_info(c->header, f.camera));
        if (a.o.backscatter)
            out.write(a.prefix + "/backscatter", when,
                      image_message(c->header, f.width, f.height, "rgb8", f.backscatter.data(), 1));
        if (a.o.noise_free)
            out.write(a.prefix + "/noise_free", when,
                      image_message(c->header, f.width, f.height, "rgb8", f.noise_free.data(), 1));
        if (a.o.depth)
            out.write(a.prefix + "/depth", when,
                      image_message(c->header, f.width, f.height, "32FC1", f.depth.data(), 4));
        ++t.rendered;
    };
    bool seen_color = false, seen_depth = false;
    for (const rosbag::MessageInstance& m : rosbag::View(in)) {
        out.write(m.getTopic(), m.getTime(), m, m.getConnectionHeader());
        if (m.getTopic() != a.color && m.getTopic() != a.depth) continue;
        const sensor_msgs::ImageConstPtr img = m.instantiate<sensor_msgs::Image>();
        if (!img) throw InputError(a.in + ": " + m.getTopic() + " is not sensor_msgs/Image");
        const std::int64_t stamp = img->header.stamp.toNSec();
        auto p = m.getTopic() == a.color ? (seen_color = true, pairer.add_color(stamp, img))
                                         : (seen_depth = true, pairer.add_depth(stamp, img));
        if (p) render(p->first, p->second);
    }
    out.close();
    in.close();
    if (!seen_color || !seen_depth)
        throw InputError(a.in + ": no messages on " + (seen_color ? a.depth : a.color) +
                         " (give --color-topic and --depth-topic)");
}

}  // namespace
}  // namespace deepsea::ros1

int main(int argc, char** argv) {
    using namespace deepsea;
    ros1::Args a;
    CLI::App app(
        "deepsea_rosbag: a bag's RGB-D frames to deep-sea images in a new bag "
        "(docs/ros.md)");
    app.add_option("--asset", a.o.asset, "baked asset (.vdb)")->required();
    app.add_option("--in", a.in, "the recorded bag")->required();
    app.add_option("-o,--out", a.out,
                   "the new bag (every message of --in plus the rendered "
                   "topics)")
        ->required();
    app.add_option("--color-topic", a.color, "colour sensor_msgs/Image topic")
        ->capture_default_str();
    app.add_option("--depth-topic", a.depth, "depth sensor_msgs/Image topic")
        ->capture_default_str();
    app.add_option("--prefix", a.prefix, "namespace of the rendered topics")->capture_default_str();
    app.add_option("--camera", a.o.camera_yaml, "setup YAML: camera (lens, sensor, ...) and snow");
    app.add_option("--exposure", a.o.exposure, "'auto' (the first pair's) or a factor")
        ->capture_default_str();
    app.add_option("--sync", a.o.sync, "exact or approximate")->capture_default_str();
    app.add_option("--slop", a.o.slop, "seconds, approximate sync")->capture_default_str();
    app.add_option("--snow", a.o.snow, "marine snow preset, or off");
    app.add_option("--snow-seed", a.o.snow_seed, "marine snow seed")->capture_default_str();
    app.add_option("--depth-scale", a.o.depth_scale, "metres per 16UC1 unit")
        ->capture_default_str();
    bool no_forward = false;
    app.add_flag("--no-forward", no_forward, "leave forward scatter out");
    app.add_flag("--shadows", a.o.shadows, "lamp shadows from the depth map");
    app.add_flag("--backscatter", a.o.backscatter, "also write <prefix>/backscatter");
    app.add_flag("--noise-free", a.o.noise_free, "also write <prefix>/noise_free (camera stage)");
    app.add_flag("--depth", a.o.depth, "also write <prefix>/depth (32FC1)");
    CLI11_PARSE(app, argc, argv);
    a.o.forward = !no_forward;
    try {
        (void)ros1::live_settings(a.o);  // options checked before the asset is read
        require_distinct(a.out, {{a.in, "the input --in"}});
        const Asset asset = load_asset(a.o.asset);
        ros1::Totals t;
        write_atomically(a.out, [&](const std::string& tmp) { ros1::convert(a, asset, tmp, t); });
        std::printf("rendered %ld of %ld pair(s), %ld malformed skipped; wrote %s\n", t.rendered,
                    t.pairs, t.malformed, a.out.c_str());
    } catch (const Error& e) {
        std::fprintf(stderr, "deepsea_rosbag: error: %s\n", e.what());
        return e.exit_code();
    } catch (const rosbag::BagException& e) {
        std::fprintf(stderr, "deepsea_rosbag: error: %s\n", e.what());
        return 4;
    }
    return 0;
}
