#pragma once
/// \file Analytic lamp irradiance for whole image rows (vectorised, float).

#include <vector>

#include "deepsea/optics/lamp_field.h"
#include "deepsea/optics/light.h"
#include "deepsea/optics/water.h"
#include "deepsea/runtime/sources.h"

namespace deepsea {

/// The rig's spotlights evaluated analytically, row by row, in structure-of-arrays form.
/// The per-pixel terms are optics' lamp.h, as in lamp_irradiance; this adds the float rows
/// (the tests check a row against lamp_irradiance to 1e-5). Given a multiple-scattering
/// asset's lamp fields (one per lamp, Asset::lamp_fields), it adds each lamp's scattered light
/// (optics' lamp_field_irradiance) to the unscattered light: all orders.
class AnalyticLamps final : public IrradianceSource {
public:
    AnalyticLamps(const Rig& rig, const Water& water, std::vector<LampField> scattered = {});
    void irradiance_row(const RowGeometry& row, float* out_rgb_planar) const override;

private:
    /// Adds each lamp's scattered light to a row (multiple-scattering assets).
    void add_scattered(const RowGeometry& row, float* out_rgb_planar) const;

    Rig m_rig;
    Water m_water;
    std::vector<LampField> m_scattered;
};

}  // namespace deepsea
