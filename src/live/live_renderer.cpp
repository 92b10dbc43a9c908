#include "deepsea/live/live_renderer.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

#include "deepsea/camera/camera_stage.h"
#include "deepsea/colour/srgb.h"
#include "deepsea/core/error.h"
#include "deepsea/runtime/layers.h"

namespace deepsea {

namespace {

/// Display values in [0, 1] to 8-bit codes, as CameraOutput::codes8 defines them.
void display_codes(const Image& display, std::vector<std::uint8_t>& codes) {
    codes.resize(display.data.size());
    for (std::size_t i = 0; i < codes.size(); ++i)
        codes[i] = std::uint8_t(std::min(std::max(display.data[i], 0.0f), 1.0f) * 255.0f + 0.5f);
}

}  // namespace

struct LiveRenderer::State {
    State(const Asset& a, LiveSettings s) : settings(std::move(s)), renderer(a, settings.render) {}

    LiveSettings settings;
    Renderer renderer;
    Layers layers;
    CameraOutput recorded;
    std::vector<std::uint8_t> codes;  ///< the streamed image's codes, swapped into the output
    std::unique_ptr<CameraStage> stage;
    Camera last;  ///< the last frame's camera
    int sizes = 0;
    double exposure = 0.0;
};

LiveRenderer::LiveRenderer(const Asset& asset, LiveSettings settings) {
    if (settings.noise_free && !settings.camera_model)
        throw ConfigError(
            "noise_free: the noise-free image is the camera stage's; give a camera "
            "model (lens, sensor, processing)");
    if (settings.camera_model && settings.backscatter)
        throw ConfigError(
            "backscatter: the layer is exposed with the exposure factor, and a "
            "camera model records frames with its own exposure; leave one out");
    m = std::make_unique<State>(asset, std::move(settings));
    if (!m->settings.camera_model && !m->settings.exposure.automatic)
        m->exposure = m->settings.exposure.factor;
}

LiveRenderer::~LiveRenderer() = default;

void LiveRenderer::note_camera() {
    const Camera& cam = m->renderer.camera();
    if (cam == m->last) return;
    m->last = cam;
    ++m->sizes;
    m->stage.reset();
}

void LiveRenderer::render(LiveFrame& out, const ColorView& color, const DepthView& depth,
                          std::uint64_t frame_key) {
    const LiveSettings& s = m->settings;
    const bool all = s.backscatter || s.depth;
    m->renderer.set_frame(frame_key);
    if (!all && !s.camera_model && m->exposure != 0.0) {
        // The image alone at a known exposure: each row encoded as the compositor finishes it,
        // while it is in cache (no final layer written and read again), into a buffer of our
        // own that becomes the output once the whole frame is done.
        const std::size_t row = 3 * std::size_t(color.width);
        m->codes.resize(row * std::size_t(color.height));
        const double exposure = m->exposure;
        m->renderer.render(m->layers, color, depth, [&](int v, const float* rgb) {
            srgb_encode(rgb, row, exposure, m->codes.data() + row * std::size_t(v));
        });
        note_camera();
        out.width = color.width;
        out.height = color.height;
        out.camera = m->renderer.camera();
        out.image.swap(m->codes);
        out.exposure = exposure;
        out.backscatter.clear();
        out.noise_free.clear();
        out.depth.clear();
        return;
    }
    m->renderer.render(m->layers, color, depth, all ? LayerSet::All : LayerSet::Final);
    note_camera();
    const Camera& cam = m->renderer.camera();
    const Image& final = m->layers.final;
    out.width = final.width;
    out.height = final.height;
    out.camera = cam;
    if (s.camera_model) {
        if (!m->stage) m->stage = std::make_unique<CameraStage>(*s.camera_model, cam);
        CameraLayerSet set;
        set.noise_free = s.noise_free;
        set.codes8 = true;
        m->stage->apply(m->recorded, final, frame_key, set);
        out.image = m->recorded.codes8;
        if (s.noise_free) display_codes(m->recorded.noise_free, out.noise_free);
        out.exposure = 0.0;
    } else {
        if (m->exposure == 0.0) m->exposure = exposure_factor(s.exposure, final);
        out.image.resize(final.data.size());
        srgb_encode(final.data.data(), final.data.size(), m->exposure, out.image.data());
        if (s.backscatter) {
            const Image& b = m->layers.backscatter;
            out.backscatter.resize(b.data.size());
            srgb_encode(b.data.data(), b.data.size(), m->exposure, out.backscatter.data());
        }
        out.exposure = m->exposure;
    }
    if (!s.noise_free) out.noise_free.clear();
    if (!s.backscatter) out.backscatter.clear();
    if (s.depth)
        out.depth = m->layers.depth.data;
    else
        out.depth.clear();
}

int LiveRenderer::sizes_seen() const { return m->sizes; }

double LiveRenderer::exposure() const { return m->exposure; }

std::string intrinsics_mismatch(const Camera& expected, const Camera& given, double rel_tol) {
    std::ostringstream o;
    o.precision(6);
    if (expected.width != given.width || expected.height != given.height) {
        o << "camera_info is " << given.width << "x" << given.height << " but the frames are "
          << expected.width << "x" << expected.height;
        return o.str();
    }
    const double tol = rel_tol * std::max(expected.fx, expected.fy);
    const std::pair<const char*, std::pair<double, double>> values[] = {
        {"fx", {given.fx, expected.fx}},
        {"fy", {given.fy, expected.fy}},
        {"cx", {given.cx, expected.cx}},
        {"cy", {given.cy, expected.cy}}};
    for (const auto& [name, v] : values) {
        if (!(std::fabs(v.first - v.second) <= tol)) {
            o << "camera_info " << name << " " << v.first << " differs from the asset camera's "
              << v.second << " (at " << expected.width << "x" << expected.height
              << "): the backscatter was baked for another camera; re-bake for this one";
            return o.str();
        }
    }
    return "";
}

}  // namespace deepsea
