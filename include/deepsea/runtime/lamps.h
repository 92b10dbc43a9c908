#pragma once
/// \file Analytic lamp irradiance for whole image rows (vectorised, float).

#include <vector>

#include "deepsea/optics/lamp_field.h"
#include "deepsea/optics/light.h"
#include "deepsea/optics/water.h"
#include "deepsea/runtime/lamp_shadows.h"
#include "deepsea/runtime/sources.h"

namespace deepsea {

/// The rig's spotlights evaluated analytically, row by row, in structure-of-arrays form.
/// The per-pixel terms are optics' lamp.h, as in lamp_irradiance; this adds the float rows
/// (the tests check a row against lamp_irradiance to 1e-5). Given a multiple-scattering
/// asset's lamp fields (one per lamp, Asset::lamp_fields), it adds each lamp's scattered light
/// (optics' lamp_field_irradiance) to the unscattered light: all orders. With shadows on, each
/// lamp's unscattered light is multiplied by its visibility from the frame's depth map
/// (LampShadows, computed in begin_frame); the scattered light is not shadowed.
class AnalyticLamps final : public IrradianceSource {
public:
    AnalyticLamps(const Rig& rig, const Water& water, std::vector<LampField> scattered = {},
                  ShadowSettings shadows = {});
    void irradiance_row(const RowGeometry& row, float* out_rgb_planar) const override;
    /// With lamp fields: the scattered light's coefficients on a grid of pixels (every
    /// 0.76 degrees seen from the camera: 8 px at fx = 600), which the frame's rows interpolate.
    /// Rows of another size, or without a begin_frame, compute their own points.
    /// With shadows on: every lamp's visibility for the frame; rows of another size, or
    /// without a begin_frame, are unshadowed.
    void begin_frame(const Camera& camera, const Image& zdepth) const override;

    /// The shadows of the last begin_frame (empty with shadows off).
    const LampShadows& shadows() const { return m_shadows; }

private:
    /// Adds each lamp's scattered light to a row (multiple-scattering assets).
    void add_scattered(const RowGeometry& row, float* out_rgb_planar) const;

    Rig m_rig;
    Water m_water;
    std::vector<LampField> m_scattered;
    ShadowSettings m_shadow_settings;
    std::vector<RidRows> m_rids;  ///< each lamp's RID for rows (tabulated lamps)
    mutable LampShadows m_shadows;
    // The frame's coefficient grid (begin_frame): planes [(j * 30 + q) * m_kx + i] and the
    // planar depth at each point [j * m_kx + i] (0: open water).
    mutable std::vector<float> m_grid, m_grid_z;
    mutable int m_kx = 0, m_ky = 0, m_width = 0, m_height = 0, m_step = 1;
};

}  // namespace deepsea
