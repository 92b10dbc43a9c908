#include "deepsea/runtime/renderer.h"

#include <string>
#include <utility>

#include "deepsea/core/error.h"
#include "deepsea/runtime/asset_backscatter.h"
#include "deepsea/runtime/compositor.h"
#include "deepsea/runtime/lamps.h"
#include "deepsea/runtime/port_backscatter.h"
#include "frame_input.h"

namespace deepsea {

namespace {

Water rendered_water(const Asset& asset, const RenderSettings& settings) {
    Water water = asset.info.water;
    if (!settings.forward) water.forward.enabled = false;
    return water;
}

}  // namespace

struct Renderer::State {
    State(const Asset& a, RenderSettings s)
        : asset(a),
          settings(std::move(s)),
          water(rendered_water(a, settings)),
          lamps(a.info.rig, water, a.lamp_fields,
                ShadowSettings{settings.shadows, settings.shadow_thickness, settings.shadow_step}) {
        if (settings.port && settings.shadows)
            throw ConfigError(
                "--shadows: lamp shadows through a port are not built yet (the "
                "shadow sweep works in the input's pinhole pixels; docs/ports.md)");
        // An asset baked through a port renders only through that port; a pinhole asset
        // renders through any (PortBackscatter's approximate lookup).
        check_port(a, settings.port, true);
        if (settings.port && settings.snow)
            throw ConfigError(
                "--snow: marine snow through a port is not built yet (particles are drawn in "
                "the input's pinhole pixels; docs/ports.md)");
        if (settings.snow) snow.emplace(*settings.snow, a.info.rig, water, a.lamp_fields);
        if (settings.port) {
            // Checked and traced now: a port that shows nothing of the frames is refused
            // before any frame is read.
            const Camera& c = settings.camera.width > 0 ? settings.camera : asset.info.camera;
            validate(*settings.port);
            check_port_view(*settings.port, c);
            rays = std::make_unique<PortRays>(*settings.port, c);
        }
    }

    /// The compositor for frames of width x height.
    Compositor& compositor(int width, int height) {
        if (!compositor_ || camera.width != width || camera.height != height) {
            compositor_.reset();
            backscatter.reset();
            camera = Camera{};
            const Camera c = frame_camera(asset.info.camera, settings.camera, width, height);
            if (settings.port) {
                if (!(rays->camera() == c)) {
                    check_port_view(*settings.port, c);
                    // (made before the old rays go: a refusal leaves them, not none)
                    auto traced = std::make_unique<PortRays>(*settings.port, c);
                    rays = std::move(traced);
                }
                // An asset baked through this port holds each pixel's water-side ray in its
                // columns, indexed by planar depth: the pinhole lookup, row by row. A pinhole
                // asset is looked up along the parallel pinhole columns (port_backscatter.h).
                if (asset.info.port)
                    backscatter = std::make_unique<AssetBackscatter>(asset, c);
                else
                    backscatter = std::make_unique<PortBackscatter>(asset, *rays);
            } else {
                backscatter = std::make_unique<AssetBackscatter>(asset, c);
            }
            compositor_ =
                std::make_unique<Compositor>(c, water, lamps, *backscatter, rays.get(),
                                             asset.forward_psf ? &*asset.forward_psf : nullptr);
            camera = c;
        }
        return *compositor_;
    }

    /// The compositor for the views' size, with `depth` filled from the depth view (planar).
    Compositor& prepare(const ColorView& color, const DepthView& depth_view) {
        if (color.width != depth_view.width || color.height != depth_view.height) {
            require_same_size(color.width, color.height, depth_view.width, depth_view.height,
                              std::string(color.name) + " and " + depth_view.name);
        }
        require_finite_color(color);
        Compositor& c = compositor(depth_view.width, depth_view.height);
        depth_image(depth_view, depth);
        to_planar_depth(camera, depth, depth_view.kind);
        return c;
    }

    Compositor& prepare(Frame& frame, DepthKind kind) {
        Compositor& c = compositor(frame.depth.width, frame.depth.height);
        to_planar_depth(camera, frame.depth, kind);
        return c;
    }

    const Asset& asset;
    RenderSettings settings;
    Water water;
    AnalyticLamps lamps;
    Camera camera;                   ///< the compositor's (width 0 before the first frame)
    std::unique_ptr<PortRays> rays;  ///< with a port: its rays for the compositor's camera
    std::unique_ptr<BackscatterSource> backscatter;
    std::unique_ptr<Compositor> compositor_;
    Image depth;  ///< a depth view's pixels, planar
    std::optional<MarineSnow> snow;

    /// Adds the snow to the layers of a frame composited with `set` over planar `zdepth`.
    void add_snow(Layers& dst, const Image& zdepth, LayerSet set) {
        if (!snow) return;
        if (set == LayerSet::All) {
            dst.snow = Image(camera.width, camera.height, 3);
            dst.snow_id = Image(camera.width, camera.height, 1);
            snow->draw(camera, zdepth, dst.final, &dst.snow, &dst.snow_id);
        } else {
            snow->draw(camera, zdepth, dst.final, nullptr, nullptr);
        }
    }

    /// With snow, a FinalRows render composites the whole image first, adds the snow, then
    /// hands over the rows.
    static void hand_over(const Image& final, const FinalRows& rows) {
        for (int v = 0; v < final.height; ++v) rows(v, final.row(v));
    }
};

Renderer::Renderer(const Asset& asset, RenderSettings settings)
    : m(std::make_unique<State>(asset, std::move(settings))) {}

Renderer::~Renderer() = default;
Renderer::Renderer(Renderer&&) noexcept = default;

void Renderer::render(Layers& dst, const ColorView& color, const DepthView& depth, LayerSet set) {
    const ColorView c = checked(color, "colour view");
    m->prepare(c, checked(depth, "depth view")).composite(dst, c, m->depth, set);
    m->add_snow(dst, m->depth, set);
}

void Renderer::render(Layers& dst, const ColorView& color, const DepthView& depth,
                      const FinalRows& rows) {
    const ColorView c = checked(color, "colour view");
    if (m->snow) {
        m->prepare(c, checked(depth, "depth view")).composite(dst, c, m->depth, LayerSet::Final);
        m->add_snow(dst, m->depth, LayerSet::Final);
        State::hand_over(dst.final, rows);
        return;
    }
    m->prepare(c, checked(depth, "depth view")).composite(dst, c, m->depth, rows);
}

void Renderer::render(Layers& dst, Frame& frame, LayerSet set, DepthKind kind) {
    m->prepare(frame, kind).composite(dst, frame, set);
    m->add_snow(dst, frame.depth, set);
}

void Renderer::render(Layers& dst, Frame& frame, const FinalRows& rows, DepthKind kind) {
    if (m->snow) {
        m->prepare(frame, kind).composite(dst, frame, LayerSet::Final);
        m->add_snow(dst, frame.depth, LayerSet::Final);
        State::hand_over(dst.final, rows);
        return;
    }
    m->prepare(frame, kind).composite(dst, frame, rows);
}

void Renderer::prepare(int width, int height) { m->compositor(width, height); }

void Renderer::set_frame(std::uint64_t frame_key, std::optional<CameraPose> pose,
                         std::optional<Shutter> shutter) {
    if (m->snow) m->snow->set_frame(frame_key, pose, shutter);
}

int Renderer::snow_drawn() const { return m->snow ? m->snow->drawn() : 0; }

const Camera& Renderer::camera() const {
    if (m->camera.width > 0) return m->camera;
    return m->settings.camera.width > 0 ? m->settings.camera : m->asset.info.camera;
}

const Water& Renderer::water() const { return m->water; }

}  // namespace deepsea
