#include "deepsea/runtime/sequence.h"

#include <tbb/parallel_pipeline.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <mutex>

#include "deepsea/core/error.h"
#include "deepsea/runtime/asset_backscatter.h"
#include "deepsea/runtime/compositor.h"
#include "deepsea/runtime/lamps.h"

namespace deepsea {

namespace {

struct Slot {
    int index = -1;
    bool skip = false;
    std::string error;
    Frame frame;
    Layers layers;  ///< filled only for jobs that write all layers
    Image final;    ///< the final layer, for the exposed image
};

bool done_already(const FrameJob& j) {
    namespace fs = std::filesystem;
    return (j.output.empty() || fs::exists(j.output)) && (j.layers.empty() || fs::exists(j.layers));
}

}  // namespace

SequenceResult render_sequence(const Asset& asset, const std::vector<FrameJob>& jobs,
                               const SequenceOptions& opt) {
    SequenceResult result;
    const auto t0 = std::chrono::steady_clock::now();
    if (jobs.empty()) return result;

    Water water = asset.info.water;
    if (!opt.forward) water.forward.enabled = false;
    const AnalyticLamps lamps(asset.info.rig, water, asset.lamp_fields);
    std::unique_ptr<AssetBackscatter> backscatter;
    std::unique_ptr<Compositor> compositor;
    Layers shared;  // jobs that want only the image composite its layers here, keep a copy
    Camera camera;
    double exposure = opt.exposure.automatic ? 0.0 : opt.exposure.factor;

    // A few slots in flight: one being read, one composited, one or two being written.
    constexpr int kTokens = 4;
    std::vector<Slot> slots(kTokens);
    int next = 0, done = 0;
    std::mutex errors_mutex;

    tbb::parallel_pipeline(
        kTokens,
        tbb::make_filter<void, Slot*>(
            tbb::filter_mode::serial_in_order,
            [&](tbb::flow_control& fc) -> Slot* {
                if (next >= int(jobs.size())) {
                    fc.stop();
                    return nullptr;
                }
                Slot* s = &slots[next % kTokens];
                s->index = next;
                s->error.clear();
                const FrameJob& job = jobs[next++];
                s->skip = opt.resume && done_already(job);
                if (s->skip) return s;
                try {
                    s->frame.rgb = read_color(job.rgb);
                    s->frame.depth = read_depth(job.depth, opt.depth_read);
                    require_same_size(s->frame.rgb, s->frame.depth, job.rgb + " and " + job.depth);
                } catch (const Error& e) {
                    s->error = e.what();
                }
                return s;
            }) &
            tbb::make_filter<Slot*, Slot*>(
                tbb::filter_mode::serial_in_order,
                [&](Slot* s) -> Slot* {
                    if (s->skip || !s->error.empty()) return s;
                    try {
                        const Image& d = s->frame.depth;
                        if (!compositor || camera.width != d.width || camera.height != d.height) {
                            camera = frame_camera(asset.info.camera, opt.camera, d.width, d.height);
                            backscatter = std::make_unique<AssetBackscatter>(asset, camera);
                            compositor =
                                std::make_unique<Compositor>(camera, water, lamps, *backscatter);
                        }
                        to_planar_depth(camera, s->frame.depth, opt.depth_kind);
                        const bool all = !jobs[s->index].layers.empty();
                        Layers& out = all ? s->layers : shared;
                        compositor->composite(out, s->frame, all ? LayerSet::All : LayerSet::Final);
                        s->final = out.final;
                        if (exposure == 0.0) exposure = exposure_factor(opt.exposure, s->final);
                    } catch (const AssetError&) {
                        throw;  // the asset does not fit these frames: stop everything
                    } catch (const Error& e) {
                        s->error = jobs[s->index].rgb + ": " + e.what();
                    }
                    return s;
                }) &
            tbb::make_filter<Slot*, void>(tbb::filter_mode::parallel, [&](Slot* s) {
                const FrameJob& job = jobs[s->index];
                if (!s->skip && s->error.empty()) {
                    try {
                        if (!job.layers.empty()) write_layers(job.layers, s->layers);
                        if (!job.output.empty()) {
                            write_color(job.output, apply_exposure(s->final, exposure), opt.bits);
                        }
                    } catch (const Error& e) {
                        s->error = e.what();
                    }
                }
                std::lock_guard<std::mutex> lock(errors_mutex);
                if (s->skip) {
                    ++result.skipped;
                } else if (s->error.empty()) {
                    ++result.written;
                } else {
                    result.errors.push_back(s->error);
                }
                ++done;
                if (opt.progress) opt.progress(done, int(jobs.size()));
            }));

    result.exposure = exposure;
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return result;
}

}  // namespace deepsea
