// The package test's consumer (tests/package): bakes a tiny asset, writes and reloads it, and
// renders one frame of a tilted plane from its own buffers (views with strides) through the
// front door, with only <deepsea/deepsea.h> and the installed libraries. Writes the frame's inputs
// (colour.exr, depth.exr) and its layers (layers.exr), which cmake_consumer_test.sh holds to
// `deepsea render` of the same files. Usage: consumer WORK_DIR. Exits 1 if the frame is wrong.
// `consumer WORK_DIR RGB DEPTH` then renders image files with that asset (relocated_test.sh:
// a TIFF, which needs the installed OpenImageIO module) into WORK_DIR/files_layers.exr.

#include <deepsea/deepsea.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

namespace {

const char* kSetup = R"(
camera: {width: 48, height: 36, fx: 40.0, fy: 40.0, cx: 23.5, cy: 17.5}
rig:
  name: one-lamp
  lights:
    - position: [0.3, 0.0, 0.0]
      direction: [-0.2, 0.0, 1.0]
      intensity: [1.0, 1.0, 1.0]
      rid: {gaussian: {sigma_deg: 35}}
water: {preset: "jerlov:IB"}
)";

int run(const std::string& dir) {
    using namespace deepsea;
    const Setup setup = parse_setup(kSetup, "consumer setup");
    require_complete(setup, "consumer setup");
    const Camera& cam = *setup.camera;

    BakeSettings settings;
    settings.step = 8;
    settings.depth_samples = 16;
    const std::string path = dir + "/tiny.vdb";
    WriteOptions options;
    options.preview = false;  // the Blender preview grids: not needed here
    write_asset(path, bake(cam, *setup.rig, *setup.water, settings), options);
    const Asset asset = load_asset(path);

    // The frame in the consumer's own memory, laid out as other programs hold images: colour
    // as RGBA floats (linear, alpha skipped by the pixel stride), depth as 16-bit millimetres
    // (ROS 16UC1) in rows padded to a multiple of 8 samples. A plane 2 m away at the top, 4 m
    // at the bottom; the right third is open water (0).
    const int W = cam.width, H = cam.height, padded = (W + 7) / 8 * 8;
    std::vector<float> rgba(std::size_t(W) * H * 4, 1.0f);
    std::vector<std::uint16_t> millimetres(std::size_t(padded) * H, 0);
    for (int v = 0; v < H; ++v) {
        for (int u = 0; u < W; ++u) {
            for (int k = 0; k < 3; ++k) rgba[(std::size_t(v) * W + u) * 4 + k] = 0.5f;
            if (u < 2 * W / 3)
                millimetres[std::size_t(v) * padded + u] = std::uint16_t(2000 + 2000 * v / H);
        }
    }
    ColorView color;
    color.data = rgba.data();
    color.width = W;
    color.height = H;
    color.type = SampleType::F32;
    color.encoding = ColorEncoding::Linear;
    color.pixel_stride = 4 * sizeof(float);
    DepthView depth;
    depth.data = millimetres.data();
    depth.width = W;
    depth.height = H;
    depth.type = SampleType::U16;
    depth.scale = 0.001;
    depth.row_stride = padded * std::ptrdiff_t(sizeof(std::uint16_t));
    Renderer renderer(asset);
    Layers layers;
    renderer.render(layers, color, depth);

    // The same frame as files, for `deepsea render` (cmake_consumer_test.sh): 0.5 is exact in
    // the EXR's half floats; depth in metres as io reads 16-bit depth (units times the scale).
    Frame frame{Image(W, H, 3, 0.5f), Image(W, H, 1)};
    for (int v = 0; v < H; ++v) {
        for (int u = 0; u < W; ++u)
            frame.depth.at(u, v) = float(double(millimetres[std::size_t(v) * padded + u]) * 0.001);
    }
    write_color(dir + "/colour.exr", frame.rgb);
    write_depth_exr(dir + "/depth.exr", frame.depth);
    // The owned frame through the same front door: the same bits as the views.
    Layers from_frame;
    renderer.render(from_frame, frame);
    if (from_frame.final.data != layers.final.data ||
        from_frame.direct.data != layers.direct.data) {
        std::fprintf(stderr, "consumer: the views and the owned frame render differently\n");
        return 1;
    }
    write_color(dir + "/final.png", layers.final);
    write_layers(dir + "/layers.exr", layers);
    std::printf("consumer: deepsea %s (%d.%d.%d)\n", DEEPSEA_VERSION_STRING, DEEPSEA_VERSION_MAJOR,
                DEEPSEA_VERSION_MINOR, DEEPSEA_VERSION_PATCH);

    // Open water shows only backscatter; the lit plane shows its direct signal on top.
    const float water = layers.final.at(cam.width - 2, cam.height / 2, 1);
    const float plane = layers.final.at(cam.width / 3, cam.height / 2, 1);
    double sum = 0.0;
    for (float x : layers.final.data) sum += x;
    const double mean = sum / double(layers.final.data.size());
    std::printf("consumer: %dx%d frame, mean final radiance %.6g, open water %.6g, plane %.6g\n",
                cam.width, cam.height, mean, water, plane);
    if (!std::isfinite(mean) || !(water > 0.0f) || !(plane > water) ||
        layers.direct.at(cam.width - 2, cam.height / 2, 1) != 0.0f) {
        std::fprintf(stderr, "consumer: unexpected frame\n");
        return 1;
    }
    return 0;
}

/// The asset of a first run, with colour and depth read from files as `deepsea render` reads
/// them.
int render_files(const std::string& dir, const std::string& rgb, const std::string& depth) {
    using namespace deepsea;
    const Asset asset = load_asset(dir + "/tiny.vdb");
    Renderer renderer(asset);
    Frame frame{read_color(rgb), read_depth(depth)};
    Layers layers;
    renderer.render(layers, frame);
    write_layers(dir + "/files_layers.exr", layers);
    std::printf("consumer: rendered %s and %s\n", rgb.c_str(), depth.c_str());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2 && argc != 4) {
        std::fprintf(stderr, "usage: consumer WORK_DIR [RGB DEPTH]\n");
        return 2;
    }
    try {
        return argc == 4 ? render_files(argv[1], argv[2], argv[3]) : run(argv[1]);
    } catch (const deepsea::Error& e) {
        std::fprintf(stderr, "consumer: error: %s\n", e.what());
        return e.exit_code();
    } catch (const std::exception& e) {
        std::fprintf(stderr, "consumer: error: %s\n", e.what());
        return 1;
    }
}
