#pragma once
/// \file Lamp shadows from the depth map (docs/snow-shadows.md, "Lamp shadows"): per lamp and
/// pixel, the fraction of the lamp's face that the depth map's surfaces leave visible.

#include <cstddef>
#include <memory>
#include <vector>

#include "deepsea/core/image.h"
#include "deepsea/optics/camera.h"
#include "deepsea/optics/light.h"
#include "deepsea/optics/shadow.h"

namespace deepsea {

/// The default ShadowSettings::step: within the measured error of docs/model.md at a quarter
/// of the full sweep's samples.
inline constexpr int kDefaultShadowStep = 2;
/// The largest step render --shadow-step takes: beyond it shadows narrower than the step, most
/// of a seafloor's, are lost.
inline constexpr int kMaxShadowStep = 8;

/// Whether and how the lamps' shadows are rendered.
struct ShadowSettings {
    bool enabled = false;
    /// How far behind a seen surface the solid extends, planar depth, metres (> 0).
    double thickness = kDefaultShadowThickness;
    /// Pixels between the swept samples along each image axis (>= 1): the sweep runs on every
    /// step-th pixel's depth and each pixel takes its visibility from the samples around it
    /// on its own surface (docs/snow-shadows.md, "Lamp shadows"); 1 sweeps every pixel (the
    /// reference the default is checked against).
    int step = kDefaultShadowStep;
};

/// Visibility of each lamp of a rig from every pixel of a frame, in [0, 1], from its planar
/// depth alone: swept on every step-th pixel (ShadowSettings::step), then brought to every
/// pixel from the swept samples on its own surface. Each lamp's epipolar lines are swept from the
/// lamp's side of the image (the epipole, or the image border toward the lamp) outward, one running
/// horizon per line (optics/shadow.h's shadow coordinate, with the thickness), so a frame costs a
/// few passes over its pixels per lamp, whatever the shadows' length. The lines depend on the
/// camera and the rig only and are kept between frames. The result is the same at any thread count.
class LampShadows {
public:
    LampShadows();
    ~LampShadows();
    LampShadows(LampShadows&&) noexcept;
    LampShadows& operator=(LampShadows&&) noexcept;

    /// Computes every lamp's visibility for the frame of planar depth `zdepth` (the camera's
    /// size; open water where has_surface says so: visibility 1 there).
    void compute(const Camera& camera, const Image& zdepth, const Rig& rig,
                 const ShadowSettings& settings);

    int width() const { return m_width; }
    int height() const { return m_height; }
    std::size_t lamps() const { return m_visibility.size(); }
    /// Lamp `lamp`'s visibility along image row v (width() values).
    const float* row(std::size_t lamp, int v) const { return m_visibility[lamp].row(v); }
    /// Lamp `lamp`'s visibility image (1 channel).
    const Image& visibility(std::size_t lamp) const { return m_visibility[lamp]; }

    struct Lines;  ///< one lamp's epipolar lines for one camera (lamp_shadows.cpp)
    /// one lamp's family of parallel lines and its arrays, swept with every other lamp's
    /// (lamp_shadows_lines.h)
    struct ParallelSweep;

private:
    /// The sweep into m_visibility (lamp_shadows.cpp) on every `step`-th pixel of the frame's
    /// planar depth `frame` along each axis (step 1: every pixel), `camera` being the camera of
    /// those pixels. The subsample (m_sub, step > 1, where a lamp is swept in the frame itself)
    /// and the transposed depth that lines along the rows are swept in are taken from `frame`
    /// in one pass.
    void sweep(const Camera& camera, const Rig& rig, float thickness, const Image& frame, int step);
    /// One lamp (at L, radius R) swept along `lines` into `vis` (lamp_shadows.cpp): on the
    /// frame, or on the transposed frame and camera (rays rx, ry to match; parallel lines only,
    /// `vis` then still the frame's). `ones`: per row of `vis`, whether it holds only 1 already
    /// (then it is not filled again). Parallel lines are not swept here but added to
    /// `parallel`, which sweep() sweeps for every lamp at once.
    void lamp_pass(const Camera& camera, const Image& zdepth, const Vec3& L, float R,
                   const Lines& lines, const float* rx, const float* ry, float thickness,
                   Image& vis, const unsigned char* ones, std::vector<ParallelSweep>& parallel);

    int m_width = 0, m_height = 0;
    std::vector<Image> m_visibility;
    std::vector<Lines> m_lines;  ///< per lamp, for m_camera and m_positions
    /// per lamp: its lines in the transposed frame where it is swept there (else none)
    std::vector<Lines> m_lines_t;
    Image m_depth_t;                ///< the swept depth, transposed
    Image m_sub;                    ///< step > 1, a lamp swept in the frame: every step-th pixel's
    Camera m_camera;                ///< the lines' camera
    std::vector<Vec3> m_positions;  ///< the lines' lamp positions
    std::vector<float> m_gf, m_gh, m_gb, m_k, m_d1, m_rx, m_ry;  ///< per pixel of the current lamp
    std::unique_ptr<LampShadows> m_coarse;  ///< the sweep on every step-th pixel (step > 1)
    /// per lamp and row of its visibility image: whether the row holds only 1 (fully lit), so
    /// that the next frame need not fill it again (most rows: shadows are sparse)
    std::vector<std::vector<unsigned char>> m_ones;
};

}  // namespace deepsea
