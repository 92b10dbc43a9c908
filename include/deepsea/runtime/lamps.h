#pragma once
/// \file Analytic lamp irradiance for whole image rows (vectorised, float).

#include <vector>

#include "deepsea/optics/light.h"
#include "deepsea/optics/water.h"
#include "deepsea/runtime/sources.h"

namespace deepsea {

/// The rig's spotlights evaluated analytically, row by row, in structure-of-arrays form.
/// Same equation as optics' lamp_irradiance (checked against it to 1e-5 in the tests).
class AnalyticLamps final : public IrradianceSource {
public:
    AnalyticLamps(const Rig& rig, const Water& water);
    void irradiance_row(const RowGeometry& row, float* out_rgb_planar) const override;

private:
    Rig m_rig;
    Water m_water;
};

}  // namespace deepsea
