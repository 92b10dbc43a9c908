#include "deepsea/camera/camera_stage.h"

#include <tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "deepsea/camera/bayer.h"
#include "deepsea/camera/noise.h"
#include "deepsea/camera/processing.h"
#include "deepsea/camera/sensor.h"
#include "deepsea/core/codes.h"
#include "deepsea/optics/schema.h"
#include "display_tables.h"
#include "rows.h"

namespace deepsea {

using camera_rows::AlignedBytes;
using camera_rows::DisplayTables;
using camera_rows::line_bytes;
using camera_rows::processing_params;
using camera_rows::Scratch;
using camera_rows::uses_table;

namespace {

const Camera& checked(const CameraModel& model, const Camera& camera) {
    validate(model);
    validate(camera);
    return camera;
}

/// n aligned floats, shared (the stage's arrays: copies of a stage share them).
std::shared_ptr<float> aligned_floats(std::size_t n) {
    AlignedBytes bytes(line_bytes<float>(n));
    const std::shared_ptr<unsigned char> owner(bytes.data.release(), AlignedBytes::Free());
    return std::shared_ptr<float>(owner, reinterpret_cast<float*>(owner.get()));
}

/// Adds a chunk's pixels (len values, whole pixels) to the histogram of their brightest raw DN
/// (whole numbers in [0, last]), their bins found in a vector loop into the exact path's index
/// scratch (free by now). One counter a bin: 16 KB at 12 bits, which stays in L1 beside the
/// sensor loop's tables (docs/camera-speed.md, "The meter's histogram").
void count_brightest(Scratch& t, int len, std::int32_t last, std::uint32_t* hist) {
    const int pixels = len / 3;
    const std::int32_t* bin = t.index;
    camera_rows::brightest_row(pixels, t.raw, last, t.index);
    for (int p = 0; p < pixels; ++p) ++hist[std::uint32_t(bin[p])];
}

/// n floats from src to dst.
void copy(const float* src, float* dst, int n) { std::memcpy(dst, src, sizeof(float) * n); }

/// The image's size and 3 channels, reusing its memory when it has them.
void ensure(Image& img, int width, int height) {
    if (img.width != width || img.height != height || img.channels != 3)
        img = Image(width, height, 3);
}

void check_exposure(const FrameExposure& e) {
    if (!(e.exposure_time_ms > 0.0 && e.exposure_time_ms <= 3.6e6))
        throw SchemaError(
            "camera.sensor.exposure_time_ms",
            "must be > 0 and at most 3.6e6 ms, got " + std::to_string(e.exposure_time_ms));
    if (!(e.system_gain > 0.0 && e.system_gain <= 1e6))
        throw SchemaError(
            "camera.sensor.system_gain",
            "must be > 0 and at most 1e6 DN per electron, got " + std::to_string(e.system_gain));
}

}  // namespace

CameraStage::CameraStage(const CameraModel& model, const Camera& intrinsics,
                         const std::optional<Port>& port)
    : m_model(model),
      m_camera(checked(model, intrinsics)),
      m_map(intrinsics, model.lens.distortion),
      m_port(port) {
    const int w = m_camera.width, h = m_camera.height;
    if (port) {
        validate(*port);
        check_port_view(*port, m_camera);
    }
    if (model.sensor.bayer != BayerPattern::None && (w < 2 || h < 2))
        throw SchemaError("camera.sensor.bayer", "needs an image of at least 2 x 2 pixels, got " +
                                                     std::to_string(w) + " x " + std::to_string(h));
    const std::size_t n = 3 * std::size_t(w), stride = camera_rows::row_stride(w);
    const std::shared_ptr<float> x2 = aligned_floats(std::size_t(w));
    for (int u = 0; u < w; ++u) {
        const double x = m_camera.ray_x(u);
        x2.get()[u] = float(x * x);
    }
    m_x2 = x2;
    // The pixels' fixed response: falloff x channel response (per millisecond) x PRNU, and
    // the DSNU, each drawn once from the seed (normal deviates, normal_row).
    const Sensor& s = m_model.sensor;
    float resp[3];
    for (int c = 0; c < 3; ++c) resp[c] = float(electrons_per_radiance(c, 1.0));
    const double prnu = s.noise ? s.prnu_percent / 100.0 : 0.0;
    const std::shared_ptr<float> response = aligned_floats(stride * h);
    const std::shared_ptr<float> dsnu =
        s.noise && s.dsnu > 0.0 ? aligned_floats(stride * h) : std::shared_ptr<float>();
    const NoiseKey prnu_key = fixed_pattern_key(s.seed, NoiseStream::Prnu);
    const NoiseKey dsnu_key = fixed_pattern_key(s.seed, NoiseStream::Dsnu);
    // The port's radiance factor per pixel and channel: the water-side radiance the layers
    // hold to the in-air radiance at the lens (the pixel's own ray, as vignetting's).
    const std::shared_ptr<float> port_factor =
        port ? aligned_floats(stride * h) : std::shared_ptr<float>();
    parallel_for(
        std::size_t(h),
        [&](std::size_t v0, std::size_t v1) {
            for (int v = int(v0); v < int(v1); ++v) {
                float* row = response.get() + stride * v;
                const double y = m_camera.ray_y(v);
                camera_rows::gain_row(m_model.lens.vignetting, x2.get(), float(y * y), resp, w,
                                      row);
                if (port_factor) {
                    float* f = port_factor.get() + stride * v;
                    for (int u = 0; u < w; ++u) {
                        const Rgb k =
                            port_radiance_factor(*port, trace_port(*port, m_camera, u, v));
                        for (int c = 0; c < 3; ++c) {
                            f[3 * u + c] = float(k[c]);
                            row[3 * u + c] *= f[3 * u + c];
                        }
                    }
                }
                camera_rows::fixed_pattern_row(prnu_key, dsnu_key, noise_counter(w, 0, v, 0),
                                               int(n), float(prnu), float(s.dsnu), row,
                                               dsnu ? dsnu.get() + stride * v : nullptr);
            }
        },
        Parallel().or_grain(8));
    m_response = response;
    m_dsnu = dsnu;
    m_port_factor = port_factor;
    if (uses_table(m_model) && m_model.processing.white_balance != WhiteBalance::GreyWorld) {
        camera_rows::ProcessParams pp;
        float scale[3];
        Rgb wb;
        processing_params(m_model, pp, scale, wb);
        m_tables = std::make_shared<const DisplayTables>(pp, scale, int(max_dn(s)) + 1);
    }
}

float CameraStage::port_factor(int u, int v, int c) const {
    if (!m_port_factor) return 1.0f;
    return m_port_factor.get()[camera_rows::row_stride(m_camera.width) * v + 3 * u + c];
}

FrameExposure CameraStage::default_exposure() const {
    return {m_model.sensor.exposure_time_ms, system_gain(m_model.sensor)};
}

double CameraStage::electrons_per_radiance(int channel, double exposure_time_ms) const {
    return deepsea::electrons_per_radiance(m_model.lens, m_model.sensor, channel, exposure_time_ms);
}

void CameraStage::apply(CameraOutput& out, const Image& radiance, std::uint64_t frame_key,
                        CameraLayerSet layers, const Parallel& par) const {
    apply(out, radiance, frame_key, default_exposure(), layers, par);
}

/// One frame's recording: its settings, tables and layers, shared by the row tasks. The first
/// pass records rows (sense_row, any order); finish() adds up what the rows counted and, for
/// grey world or a mosaic, makes the image in a second pass over the kept raw DN.
struct CameraStage::Recording {
    const CameraStage& st;
    CameraOutput& out;
    CameraLayerSet layers;
    int w, h, n;
    std::size_t stride;
    BayerPattern bayer;
    bool grey, mosaic, two_pass, keep_raw, table;
    camera_rows::SensorParams sp;
    camera_rows::ProcessParams pp;
    float resp[3], scale[3];  // resp: the noise-free image's response, no PRNU
    double range;
    // The display values and 8-bit codes of every DN: the stage's tables, or with grey world
    // this frame's (`own`, made in finish()).
    std::shared_ptr<const DisplayTables> tables;
    const float* lut = nullptr;
    const std::uint8_t* code_lut = nullptr;
    std::size_t record_row;
    AlignedBytes record;
    std::vector<double> row_sums;
    tbb::enumerable_thread_specific<std::vector<std::uint32_t>> hists;  // with layers.meter

    Recording(const CameraStage& stage, CameraOutput& o, std::uint64_t frame_key,
              const FrameExposure& exposure, CameraLayerSet set)
        : st(stage), out(o), layers(set), w(stage.m_camera.width), h(stage.m_camera.height) {
        check_exposure(exposure);
        const Sensor& s = st.m_model.sensor;
        const Processing& proc = st.m_model.processing;
        n = 3 * w;
        stride = camera_rows::row_stride(w);
        bayer = s.bayer;
        grey = proc.white_balance == WhiteBalance::GreyWorld;
        mosaic = bayer != BayerPattern::None;
        // Grey world and the demosaic need the whole frame's raw DN: a second pass makes the
        // image.
        two_pass = grey || mosaic;
        keep_raw = layers.raw || two_pass;

        sp.exposure_time_ms = float(exposure.exposure_time_ms);
        sp.dark_electrons = float(dark_electrons(s, exposure.exposure_time_ms));
        sp.full_well = float(s.full_well);
        sp.gain = float(exposure.system_gain);
        sp.black = float(black_level(s));
        sp.max_dn = float(max_dn(s));
        sp.read_noise = float(s.dark_noise);
        sp.poisson_below = float(poisson_below(s.dark_noise));
        sp.noise = s.noise;
        sp.keep_linear = layers.linear_dn;
        // The chunk's raw DN are read by the raw layer, the meter, and the processing where
        // the sensor's loop does not make the image (then it stores them whatever this says).
        sp.keep_raw = keep_raw || layers.meter;
        sp.shot_key = temporal_key(s.seed, frame_key, NoiseStream::Shot);
        sp.read_key = temporal_key(s.seed, frame_key, NoiseStream::Read);
        for (int c = 0; c < 3; ++c) resp[c] = float(st.electrons_per_radiance(c, 1.0));

        Rgb wb;
        processing_params(st.m_model, pp, scale, wb);
        range = max_dn(s) - black_level(s);
        // A table of every DN replaces the curve's arithmetic per value (uses_table).
        table = uses_table(st.m_model);
        // With a mosaic, which values each chunk's pixels record: 1 or 0 per value, for even
        // and odd rows (chunks start at even pixels).
        record_row = line_bytes<std::int32_t>(camera_rows::kChunk) / 4;
        record = AlignedBytes(mosaic ? 2 * 4 * record_row : 0);
        for (int odd = 0; odd < 2 && mosaic; ++odd)
            for (int i = 0; i < camera_rows::kChunk; ++i)
                record.at<std::int32_t>(0)[odd * record_row + i] =
                    bayer_channel(bayer, i / 3, odd) == i % 3;

        out.width = w;
        out.height = h;
        if (layers.codes8) {
            out.image = Image();
            out.codes8.resize(3 * std::size_t(w) * std::size_t(h));
        } else {
            ensure(out.image, w, h);
            out.codes8.clear();
        }
        keep_raw ? ensure(out.raw, w, h) : void(out.raw = Image());
        layers.linear_dn ? ensure(out.linear_dn, w, h) : void(out.linear_dn = Image());
        layers.noise_free ? ensure(out.noise_free, w, h) : void(out.noise_free = Image());
        out.brightest.clear();
        out.exposure = exposure;
        out.white_balance = wb;
        row_sums.assign(grey ? 3 * std::size_t(h) : 0, 0.0);
        if (table && !two_pass) use(st.m_tables);
    }

    void use(std::shared_ptr<const DisplayTables> t) {
        tables = std::move(t);
        lut = tables->lut.data();
        code_lut = tables->codes8.data();
    }

    /// Display values of `len` DN into dst, both passes: whole DN (`whole`) through this frame's
    /// table where there is one, else (and always for the noise-free DN) the processing kernel.
    void display(Scratch& t, int len, const float* dn, float* dst, bool whole) const {
        if (whole && table) {
            camera_rows::lookup_row(lut, len, dn, dst);
            return;
        }
        camera_rows::process_row(pp, len, t.scale, dn, t.tmp, t.image);
        copy(t.image, dst, len);
    }

    /// The recorded image of row v's values c0 .. c0 + len: display values, or their codes.
    void show(Scratch& t, int v, int c0, int len, const float* dn) const {
        if (!layers.codes8) return display(t, len, dn, out.image.row(v) + c0, true);
        std::uint8_t* codes = out.codes8.data() + 3 * std::size_t(w) * std::size_t(v) + c0;
        if (table) return camera_rows::lookup_codes_row(code_lut, len, dn, codes);
        display(t, len, dn, t.shown, true);
        quantise8(t.shown, len, codes);
    }

    /// This task's histogram of the brightest raw DN (layers.meter), zeros at first.
    std::uint32_t* histogram() {
        if (!layers.meter) return nullptr;
        std::vector<std::uint32_t>& hist = hists.local();
        if (hist.empty()) hist.assign(std::size_t(sp.max_dn) + 1, 0);
        return hist.data();
    }

    /// The first pass over row v: its radiance `rad` (3 x width values; `aligned`: 64-byte
    /// aligned, its chunks read in place, else each copied into the scratch first).
    void sense_row(Scratch& t, int v, const float* rad_row, bool aligned, std::uint32_t* hist) {
        const std::uint32_t base = noise_counter(w, 0, v, 0);
        const float y2 = float(st.m_camera.ray_y(v) * st.m_camera.ray_y(v));
        const Vignetting& vig = st.m_model.lens.vignetting;
        const std::int32_t last = std::int32_t(sp.max_dn);
        const bool direct = camera_rows::reads_unaligned(sp, mosaic);
        const bool in_loop = direct && table && !two_pass;  // the image made by sensor_row
        double sum[3] = {0.0, 0.0, 0.0};
        for (int c0 = 0; c0 < n; c0 += camera_rows::kChunk) {
            const int len = std::min(camera_rows::kChunk, n - c0);
            const std::size_t at = stride * v + c0;
            // The radiance read in place where sensor_row can, else copied to aligned scratch
            // (so is the noise-free DN's).
            const bool in_place = aligned || (direct && !layers.noise_free);
            const float* rad = in_place ? rad_row + c0 : t.radiance;
            if (!in_place) copy(rad_row + c0, t.radiance, len);
            camera_rows::RowBuffers rb =
                t.rows(rad, st.m_response.get() + at, st.m_dsnu ? st.m_dsnu.get() + at : t.zeros,
                       mosaic ? record.at<std::int32_t>(0) + (v & 1) * record_row : nullptr);
            if (in_loop && layers.codes8) {
                rb.code_lut = code_lut;
                rb.codes = out.codes8.data() + 3 * std::size_t(w) * std::size_t(v) + c0;
            } else if (in_loop) {
                rb.lut = lut;
                rb.shown = out.image.row(v) + c0;
            }
            camera_rows::sensor_row(sp, base + std::uint32_t(c0), len, rb);
            if (layers.linear_dn) copy(t.linear, out.linear_dn.row(v) + c0, len);
            if (keep_raw) copy(t.raw, out.raw.row(v) + c0, len);
            if (hist) count_brightest(t, len, last, hist);
            if (layers.noise_free) {  // its DN, in t.gain
                camera_rows::gain_row(vig, st.m_x2.get() + c0 / 3, y2, resp, len / 3, t.gain);
                if (st.m_port_factor) {
                    const float* f = st.m_port_factor.get() + at;
                    for (int i = 0; i < len; ++i) t.gain[i] *= f[i];
                }
                camera_rows::noise_free_row(sp, len, rad, t.gain, t.gain);
            }
            if (two_pass) {
                for (int i = 0; i < len && grey; i += 3)  // recorded values only
                    for (int c = 0; c < 3; ++c)
                        if (!mosaic || bayer_channel(bayer, (c0 + i) / 3, v) == c)
                            sum[c] += t.raw[i + c] - sp.black;
                if (layers.noise_free) copy(t.gain, out.noise_free.row(v) + c0, len);
                continue;
            }
            if (!in_loop) show(t, v, c0, len, t.raw);
            if (layers.noise_free) display(t, len, t.gain, out.noise_free.row(v) + c0, false);
        }
        if (grey)
            for (int c = 0; c < 3; ++c) row_sums[3 * std::size_t(v) + c] = sum[c];
    }

    /// After every row's first pass: the meter's histogram, then grey world's mean per channel
    /// over its recorded values (rows summed in order: the same at any thread count) and the
    /// processing pass over the kept DN, demosaiced first.
    void finish(const Parallel& par) {
        if (layers.meter) {
            out.brightest.assign(std::size_t(sp.max_dn) + 1, 0);
            for (const std::vector<std::uint32_t>& hist : hists)
                for (std::size_t b = 0; b < hist.size(); ++b) out.brightest[b] += hist[b];
        }
        if (!two_pass) return;
        if (grey) {
            Rgb sums, counts, means;
            for (int v = 0; v < h; ++v)
                for (int c = 0; c < 3; ++c) sums[c] += row_sums[3 * std::size_t(v) + c];
            for (int v = 0; v < h; ++v)
                for (int u = 0; u < 2 && u < w; ++u)  // (w - u + 1) / 2 pixels of u's parity
                    for (int c = 0; c < 3; ++c)
                        if (!mosaic || bayer_channel(bayer, u, v) == c)
                            counts[c] += (w - u + 1) / 2;
            for (int c = 0; c < 3; ++c) means[c] = sums[c] / counts[c];
            out.white_balance = grey_world_gains(means);
            for (int c = 0; c < 3; ++c) scale[c] = float(out.white_balance[c] / range);
        }
        if (table) use(std::make_shared<const DisplayTables>(pp, scale, int(sp.max_dn) + 1));
        parallel_for(
            std::size_t(h),
            [&](std::size_t v0, std::size_t v1) {
                Scratch t(w, mosaic);
                t.scales(scale);
                for (int v = int(v0); v < int(v1); ++v) {
                    if (mosaic) demosaic_row(out.raw, bayer, v, t.row);
                    for (int c0 = 0; c0 < n; c0 += camera_rows::kChunk) {
                        const int len = std::min(camera_rows::kChunk, n - c0);
                        copy(mosaic ? t.row + c0 : out.raw.row(v) + c0, t.raw, len);
                        show(t, v, c0, len, t.raw);
                        if (layers.noise_free) {
                            copy(out.noise_free.row(v) + c0, t.raw, len);
                            display(t, len, t.raw, out.noise_free.row(v) + c0, false);
                        }
                    }
                }
            },
            par.or_grain(16));
    }
};

void CameraStage::apply(CameraOutput& out, const Image& radiance, std::uint64_t frame_key,
                        const FrameExposure& exposure, CameraLayerSet layers,
                        const Parallel& par) const {
    check_exposure(exposure);
    const int w = m_camera.width, h = m_camera.height;
    require_same_size(
        radiance.width, radiance.height, w, h,
        "camera stage: the radiance image and the camera (" + describe(m_camera) + ")");
    if (radiance.channels != 3)
        throw InputError("camera stage: the radiance image has " +
                         std::to_string(radiance.channels) + " channels, not 3 (R, G, B)");
    Recording f(*this, out, frame_key, exposure, layers);
    parallel_for(
        std::size_t(h),
        [&](std::size_t v0, std::size_t v1) {
            Scratch t(w, !m_map.empty());
            t.scales(f.scale);
            std::uint32_t* hist = f.histogram();
            for (int v = int(v0); v < int(v1); ++v) {
                if (m_map.empty()) {
                    f.sense_row(t, v, radiance.row(v), false, hist);
                } else {
                    m_map.resample_row(radiance, v, t.row);
                    f.sense_row(t, v, t.row, true, hist);
                }
            }
        },
        par.or_grain(16));
    f.finish(par);
}

bool CameraStage::records_rows() const {
    return m_map.empty() && m_model.processing.white_balance != WhiteBalance::GreyWorld &&
           m_model.sensor.bayer == BayerPattern::None;
}

void CameraStage::apply_rows(CameraOutput& out,
                             const std::function<void(const RadianceRows&)>& render,
                             std::uint64_t frame_key, const FrameExposure& exposure,
                             CameraLayerSet layers) const {
    if (!records_rows())
        throw InputError(
            "camera stage: a lens distortion, grey world or a Bayer mosaic needs the whole "
            "radiance frame (apply, not apply_rows)");
    Recording f(*this, out, frame_key, exposure, layers);
    // Each thread its scratch, made on its first row (the rows come from the renderer's tasks).
    tbb::enumerable_thread_specific<std::unique_ptr<Scratch>> scratch;
    const int h = m_camera.height;
    render([&](int v, const float* rgb) {
        if (v < 0 || v >= h)
            throw InputError("camera stage: row " + std::to_string(v) +
                             " handed over, the camera (" + describe(m_camera) + ") has " +
                             std::to_string(h));
        std::unique_ptr<Scratch>& t = scratch.local();
        if (!t) {
            t = std::make_unique<Scratch>(m_camera.width, false);
            t->scales(f.scale);
        }
        f.sense_row(*t, v, rgb, false, f.histogram());
    });
    f.finish(Parallel());
}

}  // namespace deepsea
