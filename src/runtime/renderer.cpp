#include "deepsea/runtime/renderer.h"

#include <utility>

namespace deepsea {

namespace {

Water rendered_water(const Asset& asset, const RenderSettings& settings) {
    Water water = asset.info.water;
    if (!settings.forward) water.forward.enabled = false;
    return water;
}

}  // namespace

Renderer::Renderer(const Asset& asset, RenderSettings settings)
    : m_asset(asset),
      m_settings(std::move(settings)),
      m_water(rendered_water(asset, m_settings)),
      m_lamps(asset.info.rig, m_water, asset.lamp_fields) {}

Compositor& Renderer::prepare(Frame& frame, DepthKind kind) {
    const Image& d = frame.depth;
    if (!m_compositor || m_camera.width != d.width || m_camera.height != d.height) {
        m_compositor.reset();
        m_backscatter.reset();
        m_camera = Camera{};
        const Camera camera =
            frame_camera(m_asset.info.camera, m_settings.camera, d.width, d.height);
        m_backscatter = std::make_unique<AssetBackscatter>(m_asset, camera);
        m_compositor = std::make_unique<Compositor>(camera, m_water, m_lamps, *m_backscatter);
        m_camera = camera;
    }
    to_planar_depth(m_camera, frame.depth, kind);
    return *m_compositor;
}

void Renderer::render(Layers& dst, Frame& frame, LayerSet set, DepthKind kind) {
    prepare(frame, kind).composite(dst, frame, set);
}

void Renderer::render(Layers& dst, Frame& frame, const Compositor::FinalRows& rows,
                      DepthKind kind) {
    prepare(frame, kind).composite(dst, frame, rows);
}

const Camera& Renderer::camera() const {
    if (m_camera.width > 0) return m_camera;
    return m_settings.camera.width > 0 ? m_settings.camera : m_asset.info.camera;
}

}  // namespace deepsea
