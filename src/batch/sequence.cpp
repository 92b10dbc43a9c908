#include "deepsea/batch/sequence.h"

#include <tbb/parallel_pipeline.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <future>
#include <memory>
#include <mutex>
#include <new>

#include "camera_frames.h"
#include "deepsea/batch/frame_files.h"
#include "deepsea/batch/sequence_manifest.h"
#include "deepsea/core/error.h"
#include "deepsea/io/config.h"
#include "deepsea/runtime/renderer.h"
#include "manifest_writer.h"

namespace deepsea {

namespace fs = std::filesystem;

namespace {

struct Slot {
    Slot(int bits, const LayerOutput& layers) : writer(bits, layers) {}
    int index = -1;
    bool skip = false;
    std::string error;
    int error_code = 0;  ///< the exit code of the error's kind
    Frame frame;
    Layers layers;  ///< filled only for jobs that write layers
    FrameWriter writer;
    CameraOutput recorded;  ///< with a camera stage: the frame as recorded
    ExposureRecord line;    ///< with a camera stage: its settings (the controller's journal)
    ImageMetadata meta;     ///< with a camera stage: this frame's metadata
};

std::string absolute(const std::string& pattern) {
    return pattern.empty() ? pattern : fs::absolute(pattern).lexically_normal().string();
}

SequenceManifest manifest_of(const Asset& asset, const std::vector<FrameJob>& jobs,
                             const SequenceOptions& opt) {
    SequenceManifest m;
    m.deepsea_version = opt.version;
    m.asset_hash = asset.info.input_hash;
    m.rgb = absolute(opt.rgb_pattern);
    m.depth = absolute(opt.depth_pattern);
    m.camera = opt.camera.width > 0 ? opt.camera : asset.info.camera;
    if (opt.port) {
        Setup setup;
        setup.camera = m.camera;
        setup.port = opt.port;
        m.port = setup_to_yaml(setup);
    }
    if (opt.camera_model) {
        Setup setup;
        setup.camera = m.camera;
        setup.camera_model = opt.camera_model;
        m.camera_stage = setup_to_yaml(setup);
        m.auto_exposure = false;
        m.exposure = 1.0;  // the radiance goes to the camera as it is
    } else {
        m.auto_exposure = opt.exposure.automatic;
        m.percentile = opt.exposure.percentile;
        m.target = opt.exposure.target;
        m.max_clipped = opt.exposure.max_clipped;
        m.exposure = opt.exposure.automatic ? 0.0 : opt.exposure.factor;
    }
    m.image = !jobs.empty() && !jobs.front().output.empty();
    if (m.image) m.image_format = image_format(jobs.front().output);
    m.bits = opt.bits;
    m.layers = !jobs.empty() && !jobs.front().layers.empty();
    m.layer_set = opt.layer_output.describe();
    m.half = m.layers && opt.layer_output.half;
    m.forward = opt.forward;
    m.shadows = opt.shadows;
    m.shadow_step = opt.shadow_step;
    if (opt.snow) {
        m.snow = opt.snow->snow.name;
        m.snow_seed = opt.snow->seed;
        m.focus_distance_m = opt.snow->focus_distance_m;
        const Snow& sn = opt.snow->snow;
        m.snow_values = {{"concentration", sn.concentration},
                         {"d_min_mm", sn.d_min_mm},
                         {"d_max_mm", sn.d_max_mm},
                         {"slope", sn.slope},
                         {"albedo", sn.albedo},
                         {"max_distance_m", sn.max_distance_m},
                         {"streaks", opt.snow->streaks ? 1.0 : 0.0},
                         {"streak_exposure_ms", opt.snow->exposure_time_s * 1e3}};
    }
    m.poses_hash = poses_hash(jobs);
    m.poses = int(std::count_if(jobs.begin(), jobs.end(),
                                [](const FrameJob& j) { return j.pose.has_value(); }));
    m.depth_kind = opt.depth_kind == DepthKind::Range ? "range" : "z";
    m.depth_channel = opt.depth_read.channel;
    m.depth_scale = opt.depth_read.scale;
    m.frames_total = int(jobs.size());
    m.shard = opt.shard;
    return m;
}

/// Records the exception being handled as the slot's error: deepsea's errors with their
/// message (after `name` and ": " when given) and kind; running out of memory as OutOfMemory
/// naming the frame. Anything else propagates.
void record_failure(Slot& s, const std::string& name) {
    try {
        throw;
    } catch (const Error& e) {
        s.error = (name.empty() ? "" : name + ": ") + e.what();
        s.error_code = e.exit_code();
    } catch (const std::bad_alloc&) {
        const OutOfMemory oom(
            (name.empty() ? std::string("a frame") : name) +
            ": out of memory (this frame needs more memory than the machine has left)");
        s.error = oom.what();
        s.error_code = oom.exit_code();
    }
}

/// The auto exposure chosen on `job`'s frame, composited as the pipeline composites it (the
/// same layers, so the same bits of the final layer). Its failure stops the sequence.
double exposure_on(Renderer& renderer, const FrameJob& job, const SequenceOptions& opt,
                   Layers& layers) {
    Frame frame;
    Slot probe(opt.bits, opt.layer_output);
    try {
        read_frame(job, opt.depth_read, frame);
        renderer.set_frame(frame_key(job), job.pose, job.shutter);
        renderer.render(layers, frame, probe.writer.layer_set(job), opt.depth_kind);
        return exposure_factor(opt.exposure, layers.final);
    } catch (...) {
        record_failure(probe, job.rgb);
    }
    throw_error(probe.error_code, probe.error +
                                      " (the auto exposure is chosen on this frame; give "
                                      "--exposure FACTOR to render without it)");
}

}  // namespace

ImageMetadata output_metadata(const Asset& asset, double exposure, const std::string& version) {
    char factor[32];
    std::snprintf(factor, sizeof factor, "%.17g", exposure);
    ImageMetadata meta{{"deepsea:exposure", factor}, {"deepsea:asset_hash", asset.info.input_hash}};
    if (!version.empty()) meta.emplace_back("deepsea:version", version);
    return meta;
}

ImageMetadata camera_metadata(const CameraOutput& recorded, std::uint64_t frame_key) {
    const auto num = [](double v) {
        char text[32];
        std::snprintf(text, sizeof text, "%.17g", v);
        return std::string(text);
    };
    char key[24];
    std::snprintf(key, sizeof key, "%016llx", static_cast<unsigned long long>(frame_key));
    const Rgb& wb = recorded.white_balance;
    return {{"deepsea:frame_key", key},
            {"deepsea:exposure_time_ms", num(recorded.exposure.exposure_time_ms)},
            {"deepsea:system_gain", num(recorded.exposure.system_gain)},
            {"deepsea:white_balance", num(wb.r) + " " + num(wb.g) + " " + num(wb.b)}};
}

SequenceResult render_sequence(const Asset& asset, const std::vector<FrameJob>& jobs,
                               const SequenceOptions& opt) {
    SequenceResult result;
    result.total = int(jobs.size());
    const auto t0 = std::chrono::steady_clock::now();
    if (jobs.empty()) return result;

    // The manifests: refuse another sequence's folder, or a resume with other settings; keep
    // the exposure the folder's frames were made with.
    SequenceManifest record = manifest_of(asset, jobs, opt);
    bool recorded = false;  // the manifests hold an exposure: frames may be written
    for (const std::string& path : opt.manifests) {
        if (!fs::exists(path)) continue;
        const SequenceManifest folder = read_manifest(path);
        if (!opt.resume) {
            check_same_inputs(folder, record, path);
            continue;
        }
        check_resumable(folder, record, path);
        if (folder.exposure > 0.0 && !recorded) {
            record.exposure = folder.exposure;
            record.exposure_frame = folder.exposure_frame;
            recorded = true;
        }
    }
    if (opt.resume && !opt.manifests.empty() && !recorded) {
        for (const FrameJob& j : jobs) {
            for (const std::string& out : {j.output, j.layers}) {
                if (!out.empty() && fs::exists(out)) {
                    throw InputError(out + ": cannot resume: no " + std::string(kManifestName) +
                                     " records the exposure of the frames there; render "
                                     "without --resume to start again");
                }
            }
        }
    }

    if (opt.camera_model && !opt.layer_output.camera)
        throw InputError("render_sequence: a camera stage needs layer_output.camera");
    RenderSettings settings;
    settings.camera = opt.camera;
    settings.forward = opt.forward;
    settings.shadows = opt.shadows;
    settings.shadow_step = opt.shadow_step;
    settings.port = opt.port;
    settings.snow = opt.snow;
    Renderer renderer(asset, settings);
    // The compositor (the forward scatter's fit, the backscatter's row bounds: 20-30 ms at
    // 800x800) is made on a thread of its own for the size the frames should have, while the
    // pipeline reads the first frames; the first composite waits for it. A failure is left to
    // that frame, which meets it again with its name. Not with one thread, nor on a resume,
    // which may skip every frame.
    std::future<void> made;
    if (!opt.resume && tbb::this_task_arena::max_concurrency() > 1) {
        const Camera& c = opt.camera.width > 0 ? opt.camera : asset.info.camera;
        made = std::async(std::launch::async, [&renderer, c] {
            try {
                renderer.prepare(c.width, c.height);
            } catch (...) {
            }
        });
    }
    const auto compositor_made = [&made] {
        if (made.valid()) made.get();
    };
    std::optional<CameraFrames> camera;
    if (opt.camera_model) camera.emplace(*opt.camera_model, opt.port, opt.manifests, opt.resume);
    Layers shared;  // jobs that want only the image composite its layers here, keep a copy
    double exposure = record.exposure;
    ImageMetadata meta;
    if (opt.exposure_frame && !opt.camera_model && exposure == 0.0) {
        compositor_made();
        exposure = exposure_on(renderer, *opt.exposure_frame, opt, shared);
        record.exposure_frame = opt.exposure_frame->rgb;
    }

    // Two slots in flight: one frame composited while the next is read or the last written.
    // Each holds its frame's inputs and codes (a 1080p frame: 6 MB of 8-bit colour codes, 8 MB
    // of float depth, 6 MB of output codes). A third slot (one read, one composited, one
    // written) gave the same frame rates on 2 cores, within 1 %, over three alternated runs of
    // `deepsea bench --cases sequence`, for 19 MB more at 1080p.
    constexpr int kTokens = 2;
    // A slot is taken when a frame is read and given back when it is written: the writers run
    // in parallel and finish out of order, so a slot is reused only once its frame is done.
    std::vector<Slot> slots(kTokens, Slot(opt.bits, opt.layer_output));
    std::vector<Slot*> free_slots;
    for (Slot& slot : slots) free_slots.push_back(&slot);
    int next = 0, done = 0;
    std::mutex mutex;  // result, record and free_slots
    std::atomic<bool> stop{opt.progress && !opt.progress(0, int(jobs.size()))};
    // The manifest files are written outside `mutex`, by the writer's thread, from copies of
    // `record` taken under it: the reader needs `mutex` for a free slot, and a manifest's
    // fsync (milliseconds, tens on a busy disk) held it after every frame. Copies are posted
    // in the order frames finish, so the count on disk only grows and never counts a frame
    // not yet written.
    ManifestWriter manifests(opt.manifests);
    const auto snapshot = [&]() -> const SequenceManifest& {  // with `mutex` held
        record.frames_done = result.written + result.skipped;
        return record;
    };

    tbb::parallel_pipeline(
        kTokens,
        tbb::make_filter<void, Slot*>(
            tbb::filter_mode::serial_in_order,
            [&](tbb::flow_control& fc) -> Slot* {
                if (next >= int(jobs.size()) || stop) {
                    fc.stop();
                    return nullptr;
                }
                Slot* s = nullptr;
                {
                    std::lock_guard<std::mutex> lock(mutex);
                    s = free_slots.back();  // the pipeline holds at most kTokens frames
                    free_slots.pop_back();
                }
                s->index = next;
                s->error.clear();
                s->error_code = 0;
                const FrameJob& job = jobs[next++];
                s->skip = opt.resume && outputs_complete(job, opt.layer_output) &&
                          (!camera || camera->can_skip(job));
                if (s->skip) return s;
                try {
                    read_frame(job, opt.depth_read, s->frame);  // into the slot's buffers
                } catch (...) {
                    record_failure(*s, "");
                }
                return s;
            }) &
            tbb::make_filter<Slot*, Slot*>(
                tbb::filter_mode::serial_in_order,
                [&](Slot* s) -> Slot* {
                    compositor_made();
                    if (s->skip && camera) camera->skipped(jobs[s->index]);
                    if (s->skip || !s->error.empty()) return s;
                    try {
                        const FrameJob& job = jobs[s->index];
                        // Jobs that want only the image composite into `shared`; the
                        // writer keeps what it needs of it (PNG and JPEG codes: a quarter
                        // of the float image). Once the exposure is known, such an image
                        // is encoded row by row as the compositor finishes it, and no
                        // float image is kept.
                        Layers& out = job.layers.empty() ? shared : s->layers;
                        renderer.set_frame(frame_key(job), job.pose, job.shutter);
                        if (camera) {
                            // The image alone: each row recorded as the compositor finishes
                            // it (no radiance frame), where the stage needs no whole frame.
                            const Camera cam =
                                frame_camera(asset.info.camera, opt.camera, s->frame.depth.width,
                                             s->frame.depth.height);
                            if (job.layers.empty() && camera->records_rows(cam)) {
                                camera->record_rows(
                                    cam, job,
                                    [&](const CameraStage::RadianceRows& rows) {
                                        renderer.render(out, s->frame, rows, opt.depth_kind);
                                    },
                                    s->writer.camera_set(job), s->recorded, s->line);
                            } else {
                                renderer.render(out, s->frame, s->writer.layer_set(job),
                                                opt.depth_kind);
                                camera->record(renderer.camera(), job, out.final,
                                               s->writer.camera_set(job), s->recorded, s->line);
                            }
                            s->meta = camera_metadata(s->recorded, frame_key(job));
                            result.camera_exposure = s->recorded.exposure;
                        } else if (s->writer.streams(job, exposure)) {
                            const Image& z = s->frame.depth;
                            renderer.render(
                                out, s->frame,
                                s->writer.streaming_rows(job, z.width, z.height, exposure),
                                opt.depth_kind);
                        } else {
                            renderer.render(out, s->frame, s->writer.layer_set(job),
                                            opt.depth_kind);
                            if (exposure == 0.0) {
                                exposure = exposure_factor(opt.exposure, out.final);
                                record.exposure_frame = job.rgb;
                            }
                            s->writer.keep(job, out, exposure);
                        }
                    } catch (const AssetError& e) {
                        // The asset does not fit the first frame composited: it fits none
                        // of the sequence, stop everything. A later frame of another shape
                        // fails alone.
                        if (meta.empty()) throw AssetError(jobs[s->index].rgb + ": " + e.what());
                        record_failure(*s, jobs[s->index].rgb);
                    } catch (const ConfigError& e) {
                        // The camera stage refuses the first frame's camera (a lens
                        // that folds it over): so every frame of its size.
                        if (meta.empty()) throw ConfigError(jobs[s->index].rgb + ": " + e.what());
                        record_failure(*s, jobs[s->index].rgb);
                    } catch (...) {
                        record_failure(*s, jobs[s->index].rgb);
                    }
                    if (s->error.empty() && meta.empty()) {
                        meta = output_metadata(asset, exposure, opt.version);
                        if (opt.camera_model) {  // no exposure factor: the camera's
                            meta.erase(std::remove_if(meta.begin(), meta.end(),
                                                      [](const auto& kv) {
                                                          return kv.first == "deepsea:exposure";
                                                      }),
                                       meta.end());
                        }
                        // Before the first output (this filter is serial and the writers
                        // take only frames it has passed): a kill from here on leaves
                        // manifests that hold the exposure of every frame written. A
                        // manifest that cannot be written stops everything.
                        SequenceManifest first;
                        {
                            std::lock_guard<std::mutex> lock(mutex);
                            record.exposure = exposure;
                            first = snapshot();
                        }
                        manifests.write_now(first);
                        recorded = true;
                    }
                    return s;
                }) &
            tbb::make_filter<Slot*, void>(tbb::filter_mode::parallel, [&](Slot* s) {
                const FrameJob& job = jobs[s->index];
                if (!s->skip && s->error.empty()) {
                    try {
                        if (opt.camera_model) {
                            ImageMetadata m = meta;
                            m.insert(m.end(), s->meta.begin(), s->meta.end());
                            s->writer.write(job, s->layers, s->recorded, m);
                        } else {
                            s->writer.write(job, s->layers, meta, exposure);
                        }
                    } catch (...) {
                        record_failure(*s, "");
                    }
                }
                std::lock_guard<std::mutex> lock(mutex);
                if (opt.on_frame && (s->skip || s->error.empty())) opt.on_frame(job, s->skip);
                if (s->skip) {
                    ++result.skipped;
                } else if (s->error.empty()) {
                    ++result.written;
                    if (camera && camera->controller()) camera->written(s->line);
                    manifests.post(snapshot());
                } else {
                    result.errors.push_back(s->error);
                    result.error_codes.push_back(s->error_code);
                }
                ++done;
                free_slots.push_back(s);
                if (opt.progress && !opt.progress(done, int(jobs.size()))) stop = true;
            }));

    // The last manifest on this thread, after those posted: every frame of the run is counted
    // when this returns, and the file's bytes are those of a write after every frame.
    if (recorded) {
        std::unique_lock<std::mutex> lock(mutex);  // (the pipeline's threads are done)
        const SequenceManifest last = snapshot();
        lock.unlock();
        manifests.write_now(last);
    }
    result.interrupted = done < int(jobs.size());
    result.exposure = exposure;
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return result;
}

}  // namespace deepsea
