// The package test's consumer (tests/package): bakes a tiny asset, writes and reloads it, and
// renders one frame of a tilted plane from its own buffers through the front door, with only
// <deepsea/deepsea.h> and the installed libraries. Writes the frame's inputs (colour.exr,
// depth.exr) and its layers (layers.exr), which cmake_consumer_test.sh holds to `deepsea render`
// of the same files. Usage: consumer WORK_DIR. Exits 1 if the frame is wrong.

#include <deepsea/deepsea.h>

#include <cmath>
#include <cstdio>
#include <exception>
#include <string>

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

    // A plane 2 m away at the top, 4 m at the bottom; the right third is open water.
    Frame frame{Image(cam.width, cam.height, 3, 0.5f), Image(cam.width, cam.height, 1)};
    for (int v = 0; v < cam.height; ++v) {
        for (int u = 0; u < cam.width; ++u) {
            frame.depth.at(u, v) =
                u < 2 * cam.width / 3 ? float(2.0 + 2.0 * v / cam.height) : INFINITY;
        }
    }
    write_color(dir + "/colour.exr", frame.rgb);  // 0.5: exact in the EXR's half floats too
    write_depth_exr(dir + "/depth.exr", frame.depth);
    Renderer renderer(asset);
    Layers layers;
    renderer.render(layers, frame);
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

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: consumer WORK_DIR\n");
        return 2;
    }
    try {
        return run(argv[1]);
    } catch (const deepsea::Error& e) {
        std::fprintf(stderr, "consumer: error: %s\n", e.what());
        return e.exit_code();
    } catch (const std::exception& e) {
        std::fprintf(stderr, "consumer: error: %s\n", e.what());
        return 1;
    }
}
