#include "deepsea/runtime/marine_snow.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "deepsea/core/random.h"
#include "deepsea/optics/schema.h"
#include "deepsea/optics/transmission.h"
#include "deepsea/runtime/snow_light.h"
#include "snow_place.h"

namespace deepsea {

namespace {

/// Cells hold this many particles on average at most (their edge shrinks in dense snow), so
/// that Poisson counts by inversion stay short and cells fit the view's edges.
constexpr double kMaxPerCell = 32.0;
constexpr double kMaxCell = 0.5;  ///< metres
/// The random numbers' stream for snow (another stream than any camera noise's).
constexpr std::uint64_t kSnowStream = 0x736e6f775f706172ull;  // "snow_par"

/// Poisson(lambda) by inversion (Knuth): lambda <= kMaxPerCell keeps exp(-lambda) far above
/// the smallest double.
int poisson(double lambda, Rng& rng) {
    const double limit = std::exp(-lambda);
    int k = 0;
    double p = rng.uniform();
    while (p > limit) {
        ++k;
        p *= rng.uniform();
    }
    return k;
}

std::uint64_t pack(long long i, long long j, long long k) {
    const auto b = [](long long x) { return std::uint64_t(x) & ((1ull << 21) - 1); };
    return b(i) | (b(j) << 21) | (b(k) << 42);
}

struct View {
    double xl, xr, yt, yb;  ///< the image rectangle's edges as x / z and y / z
    double z0, z1;          ///< planar depth range
};

/// Whether a sphere (camera-frame centre c, radius r) may meet the view.
bool may_meet(const View& v, const Vec3& c, double r) {
    if (c.z < v.z0 - r || c.z > v.z1 + r) return false;
    if (c.x - v.xl * c.z < -r * std::sqrt(1.0 + v.xl * v.xl)) return false;
    if (v.xr * c.z - c.x < -r * std::sqrt(1.0 + v.xr * v.xr)) return false;
    if (c.y - v.yt * c.z < -r * std::sqrt(1.0 + v.yt * v.yt)) return false;
    if (v.yb * c.z - c.y < -r * std::sqrt(1.0 + v.yb * v.yb)) return false;
    return true;
}

}  // namespace

void validate(const SnowSettings& s) {
    validate(s.snow);
    if (!(s.focus_distance_m > 0.0) || !(s.focus_distance_m <= 1e4))
        throw SchemaError(
            "camera.lens.focus_distance_m",
            "must be > 0 and at most 10000 metres, got " + std::to_string(s.focus_distance_m));
    if (!(s.f_number > 0.0)) throw SchemaError("camera.lens.f_number", "must be > 0");
    if (!(s.pixel_pitch_um > 0.0)) throw SchemaError("camera.sensor.pixel_pitch_um", "must be > 0");
    if (!(s.exposure_time_s > 0.0) || !(s.exposure_time_s <= 10.0))
        throw SchemaError("snow.exposure_time_ms", "must be > 0 and at most 10000 ms, got " +
                                                       std::to_string(s.exposure_time_s * 1e3));
    if (!(s.frame_rate_hz >= 0.0) || !(s.frame_rate_hz <= 1e4))
        throw SchemaError("snow.frame_rate_hz",
                          "must be in (0, 10000] frames per second (0: not given)");
}

namespace {

/// Cell (i, j, k)'s particles from its random numbers (keyed by `base` and the cell): a Poisson
/// count, then per particle its own stream's first three numbers (the place) and fourth (the
/// size spectrum's quantile).
void generate_cell(std::uint64_t base, long long i, long long j, long long k, double cell,
                   double lambda, std::vector<CellParticle>& out) {
    const std::uint64_t key = mix_seed(base, pack(i, j, k));
    Rng rng(key);
    const int n = poisson(lambda, rng);
    out.resize(std::size_t(n));
    for (int q = 0; q < n; ++q) {
        Rng pr(mix_seed(key, std::uint64_t(q) + 1));
        CellParticle& c = out[std::size_t(q)];
        // (three statements: the numbers in the order x, y, z)
        c.x = (double(i) + pr.uniform()) * cell;
        c.y = (double(j) + pr.uniform()) * cell;
        c.z = (double(k) + pr.uniform()) * cell;
        c.q = pr.uniform();
    }
}

}  // namespace

void place_snow(const SnowSettings& s, const Camera& cam, std::uint64_t frame_key,
                const std::optional<CameraPose>& pose, const Image* zdepth, SnowPlacing& placing,
                std::vector<SnowParticle>& all) {
    const Snow& snow = s.snow;
    const View v{cam.ray_x(-0.5), cam.ray_x(cam.width - 0.5),
                 cam.ray_y(-0.5), cam.ray_y(cam.height - 0.5),
                 kSnowNearM,      snow.max_distance_m};
    const CameraPose p = pose ? *pose : CameraPose{};
    // Without a pose every frame has its own cells: the frame key is part of their key.
    const std::uint64_t base =
        mix_seed(s.seed ^ kSnowStream, pose ? 0x706f736564ull : frame_key, pose ? 1 : 2);
    const double cell = std::min(kMaxCell, std::cbrt(kMaxPerCell / snow.concentration));
    const double lambda = snow.concentration * cell * cell * cell;
    // With a pose the cells are the world's and keep their particles from frame to frame;
    // kept cells made with another key or edge are not these.
    const bool keep = pose.has_value();
    if (!keep || placing.base != base || placing.cell != cell) {
        placing.index.clear();
        placing.free.clear();
        for (std::size_t slot = 0; slot < placing.slots.size(); ++slot)
            placing.free.push_back(std::uint32_t(slot));
        placing.base = base;
        placing.cell = cell;
    }
    const std::uint32_t frame = ++placing.frame;

    // The world box of the view's corners, in cells.
    Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    for (const double z : {v.z0, v.z1})
        for (const double x : {v.xl, v.xr})
            for (const double y : {v.yt, v.yb}) {
                const Vec3 w = p.origin + p.right * (x * z) + p.down * (y * z) + p.forward * z;
                lo = {std::min(lo.x, w.x), std::min(lo.y, w.y), std::min(lo.z, w.z)};
                hi = {std::max(hi.x, w.x), std::max(hi.y, w.y), std::max(hi.z, w.z)};
            }
    const long long i0 = (long long)std::floor(lo.x / cell),
                    i1 = (long long)std::floor(hi.x / cell);
    const long long j0 = (long long)std::floor(lo.y / cell),
                    j1 = (long long)std::floor(hi.y / cell);
    const long long k0 = (long long)std::floor(lo.z / cell),
                    k1 = (long long)std::floor(hi.z / cell);
    const double r = cell * std::sqrt(3.0) / 2.0;
    const int W = cam.width, H = cam.height;
    if (zdepth) require_same_size(zdepth->width, zdepth->height, W, H, "marine snow's depth");

    const SnowSizes sizes(snow);
    // One list per slab of cells (i), joined in order: the same particles at any thread count.
    const std::size_t nslabs = std::size_t(i1 - i0 + 1);
    std::vector<std::vector<SnowParticle>>& slabs = placing.slabs;
    slabs.resize(nslabs);
    if (placing.fresh.size() < nslabs) placing.fresh.resize(nslabs);
    if (placing.fresh_keys.size() < nslabs) placing.fresh_keys.resize(nslabs);
    std::vector<std::size_t> made(nslabs, 0);  // per slab: cells generated this frame
    tbb::parallel_for(tbb::blocked_range<long long>(i0, i1 + 1), [&](const auto& range) {
        for (long long i = range.begin(); i != range.end(); ++i) {
            const std::size_t b = std::size_t(i - i0);
            std::vector<SnowParticle>& out = slabs[b];
            std::vector<std::vector<CellParticle>>& fresh = placing.fresh[b];
            std::vector<CellKey>& fresh_keys = placing.fresh_keys[b];
            out.clear();
            fresh_keys.clear();
            std::size_t nf = 0;
            for (long long j = j0; j <= j1; ++j)
                for (long long k = k0; k <= k1; ++k) {
                    const Vec3 centre{(double(i) + 0.5) * cell, (double(j) + 0.5) * cell,
                                      (double(k) + 0.5) * cell};
                    if (!may_meet(v, to_camera(p, centre), r)) continue;
                    // (the index is only read here; cells made now join it after the slabs)
                    const std::vector<CellParticle>* cp = nullptr;
                    if (keep) {
                        const auto it = placing.index.find(CellKey{i, j, k});
                        if (it != placing.index.end()) {
                            placing.last_used[it->second] = frame;  // each slot one cell's
                            cp = &placing.slots[it->second];
                        }
                    }
                    if (!cp) {
                        if (fresh.size() <= nf) fresh.resize(nf + 1);
                        generate_cell(base, i, j, k, cell, lambda, fresh[nf]);
                        if (keep) fresh_keys.push_back(CellKey{i, j, k});
                        cp = &fresh[nf++];
                    }
                    for (const CellParticle& cq : *cp) {
                        const Vec3 c = to_camera(p, Vec3{cq.x, cq.y, cq.z});
                        if (!(c.z >= v.z0 && c.z <= v.z1)) continue;
                        const double x = c.x / c.z, y = c.y / c.z;
                        if (x < v.xl || x >= v.xr || y < v.yt || y >= v.yb) continue;
                        if (zdepth) {
                            // MarineSnow::draw's pixel and test (a surface at or before the
                            // centre, open water being none)
                            const double u = cam.fx * c.x / c.z + cam.cx,
                                         vv = cam.fy * c.y / c.z + cam.cy;
                            const float zs = zdepth->row(
                                std::clamp(iround(vv), 0, H - 1))[std::clamp(iround(u), 0, W - 1)];
                            if (zs > 0.0f && zs <= float(c.z)) {
                                out.push_back({c, -1.0, 0});  // no size: 0 below
                                continue;
                            }
                        }
                        // the quantile, made a diameter below for particles in view only
                        out.push_back({c, cq.q, 0});
                    }
                }
            made[b] = nf;
            // The slab's sizes in rows (vectorised, snow_diameters).
            thread_local std::vector<double> qs;
            qs.clear();
            for (const SnowParticle& pt : out)
                if (pt.diameter >= 0.0) qs.push_back(pt.diameter);
            snow_diameters(sizes, qs.data(), int(qs.size()));
            std::size_t m = 0;
            for (SnowParticle& pt : out) pt.diameter = pt.diameter >= 0.0 ? qs[m++] : 0.0;
        }
    });
    if (keep) {
        // Cells the view no longer meets give their slots up; those made now take slots (their
        // particles' memory swapped in, the slot's old memory left for the next cells made).
        for (auto it = placing.index.begin(); it != placing.index.end();) {
            if (placing.last_used[it->second] != frame) {
                placing.free.push_back(it->second);
                it = placing.index.erase(it);
            } else {
                ++it;
            }
        }
        for (std::size_t b = 0; b < nslabs; ++b)
            for (std::size_t f = 0; f < made[b]; ++f) {
                std::uint32_t slot;
                if (!placing.free.empty()) {
                    slot = placing.free.back();
                    placing.free.pop_back();
                } else {
                    slot = std::uint32_t(placing.slots.size());
                    placing.slots.emplace_back();
                    placing.last_used.push_back(0);
                }
                placing.slots[slot].swap(placing.fresh[b][f]);
                placing.last_used[slot] = frame;
                placing.index.emplace(placing.fresh_keys[b][f], slot);
            }
    }
    // Joined in parallel: each slab's particles after the slabs before, ids 1, 2, ... in order.
    std::vector<std::size_t> at(slabs.size() + 1, 0);
    for (std::size_t b = 0; b < slabs.size(); ++b) at[b + 1] = at[b] + slabs[b].size();
    all.resize(at.back());
    tbb::parallel_for(std::size_t(0), slabs.size(), [&](std::size_t b) {
        for (std::size_t q = 0; q < slabs[b].size(); ++q) {
            all[at[b] + q] = slabs[b][q];
            all[at[b] + q].id = std::uint32_t(at[b] + q + 1);
        }
    });
}

std::vector<SnowParticle> snow_particles(const SnowSettings& s, const Camera& cam,
                                         std::uint64_t frame_key,
                                         const std::optional<CameraPose>& pose) {
    SnowPlacing placing;
    std::vector<SnowParticle> all;
    place_snow(s, cam, frame_key, pose, nullptr, placing, all);
    return all;
}

MarineSnow::MarineSnow(SnowSettings settings, const Rig& rig, const Water& water,
                       std::vector<LampField> scattered)
    : m_settings(std::move(settings)),
      m_rig(rig),
      m_water(water),
      m_scattered(std::move(scattered)) {
    validate(m_settings);
    if (!m_scattered.empty() && m_scattered.size() != m_rig.lights.size())
        throw std::invalid_argument("MarineSnow: one lamp field per lamp");
}

void MarineSnow::set_frame(std::uint64_t frame_key, std::optional<CameraPose> pose,
                           std::optional<Shutter> shutter) {
    m_key = frame_key;
    m_pose = pose;
    m_shutter = shutter;
}

}  // namespace deepsea
