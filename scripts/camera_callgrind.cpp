// The bench's `camera` case (tools/deepsea/cmd_bench.cpp: the default camera model, the image
// alone) as a program of its own, for callgrind, its exposure time filling G's full well at
// G's 99.5th percentile (the bench's white is the automatic exposure's, from the luminance): a
// rendered frame's final radiance layer (EXR) recorded `frames` times at a size (nearest resample),
// so that the instructions per frame are (N frames - 1 frame) / (N - 1) with the process's start,
// the file and the stage's fixed patterns cancelling. Built and run by scripts/camera-callgrind.sh.
// An optional fifth argument records other layers: `codes` (the 8-bit codes of a PNG or JPEG
// sequence, the bench's camera-codes), `meter` (the codes and the auto-exposure meter's
// histogram, as a sequence with auto exposure records them).
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "deepsea/camera/camera_stage.h"

using namespace deepsea;

namespace {

Image load_final(const char* path) {
    Imf::InputFile f(path);
    const auto dw = f.header().dataWindow();
    const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
    Image img(w, h, 3);
    Imf::FrameBuffer fb;
    const char* names[3] = {"final.R", "final.G", "final.B"};
    for (int c = 0; c < 3; ++c)
        fb.insert(names[c], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(img.data.data() + c), 12,
                                       12 * std::size_t(w)));
    f.setFrameBuffer(fb);
    f.readPixels(dw.min.y, dw.max.y);
    return img;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 5 && argc != 6) {
        std::fprintf(stderr,
                     "usage: camera_callgrind layers.exr width height frames [codes|meter]\n");
        return 2;
    }
    const Image src = load_final(argv[1]);
    const int w = std::atoi(argv[2]), h = std::atoi(argv[3]), frames = std::atoi(argv[4]);
    Image rad(w, h, 3);
    for (int v = 0; v < h; ++v)
        for (int u = 0; u < w; ++u)
            for (int c = 0; c < 3; ++c)
                rad.data[rad.index(u, v, c)] =
                    src.data[src.index(u * src.width / w, v * src.height / h, c)];
    // White: G's 99.5th percentile.
    std::vector<float> g;
    for (std::size_t i = 1; i < rad.data.size(); i += 3) g.push_back(rad.data[i]);
    std::nth_element(g.begin(), g.begin() + std::ptrdiff_t(g.size() * 995 / 1000), g.end());
    const double white = g[g.size() * 995 / 1000];
    Camera cam;
    cam.width = w, cam.height = h, cam.fx = cam.fy = 600.0 * w / 800.0;
    cam.cx = w / 2.0, cam.cy = h / 2.0;
    CameraModel model;
    const CameraStage probe(model, cam);
    model.sensor.exposure_time_ms =
        model.sensor.full_well / (white * probe.electrons_per_radiance(1, 1.0));
    const CameraStage stage(model, cam);
    CameraOutput out;
    CameraLayerSet layers;
    const std::string what = argc == 6 ? argv[5] : "";
    layers.codes8 = what == "codes" || what == "meter";
    layers.meter = what == "meter";
    for (int k = 0; k < frames; ++k) stage.apply(out, rad, std::uint64_t(k), layers);
    unsigned long long hash = 0;  // of the last frame's image, codes and meter, to compare builds
    for (const float x : out.image.data) hash = hash * 31 + (unsigned long long)(x * 1e6f);
    for (const std::uint8_t c : out.codes8) hash = hash * 31 + c;
    for (const std::uint32_t b : out.brightest) hash = hash * 31 + b;
    std::printf("%dx%d frames %d hash %llx\n", w, h, frames, hash);
}
