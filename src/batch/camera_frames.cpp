#include "camera_frames.h"

#include <filesystem>

#include "deepsea/camera/auto_exposure.h"

namespace deepsea {

namespace fs = std::filesystem;

namespace {

/// A journal line's frame: the colour file's absolute path (the manifest's inputs are absolute
/// too), so that a resume from another working folder finds its lines.
std::string journal_name(const FrameJob& job) {
    return fs::absolute(job.rgb).lexically_normal().string();
}

}  // namespace

CameraFrames::CameraFrames(const CameraModel& model, const std::optional<Port>& port,
                           const std::vector<std::string>& manifests, bool resume)
    : m_model(model), m_port(port), m_next(first_exposure(model)) {
    if (!controller()) return;
    for (const std::string& manifest : manifests) {
        const std::string journal =
            (fs::path(manifest).parent_path() / kExposureJournalName).string();
        m_journals.push_back(journal);
        if (resume && m_read.empty()) {
            m_read = read_exposure_journal(journal);
        } else if (!resume) {
            std::error_code ec;
            fs::remove(journal, ec);  // an earlier run's: its frames are made again
        }
    }
}

bool CameraFrames::can_skip(const FrameJob& job) const {
    return !controller() || m_read.count(journal_name(job)) > 0;
}

void CameraFrames::skipped(const FrameJob& job) {
    if (controller()) m_next = m_read.at(journal_name(job)).next;
}

const CameraStage& CameraFrames::stage(const Camera& camera) {
    if (!m_stage || !(m_stage->camera() == camera))
        m_stage = std::make_unique<CameraStage>(m_model, camera, m_port);
    return *m_stage;
}

bool CameraFrames::records_rows(const Camera& camera) { return stage(camera).records_rows(); }

void CameraFrames::record(const Camera& camera, const FrameJob& job, const Image& radiance,
                          CameraLayerSet layers, CameraOutput& out, ExposureRecord& line) {
    if (controller()) layers.meter = true;  // the meter's histogram of the raw DN
    stage(camera).apply(out, radiance, frame_key(job), m_next, layers);
    step(job, out, line);
}

void CameraFrames::record_rows(const Camera& camera, const FrameJob& job,
                               const std::function<void(const CameraStage::RadianceRows&)>& render,
                               CameraLayerSet layers, CameraOutput& out, ExposureRecord& line) {
    if (controller()) layers.meter = true;
    stage(camera).apply_rows(out, render, frame_key(job), m_next, layers);
    step(job, out, line);
}

void CameraFrames::step(const FrameJob& job, const CameraOutput& out, ExposureRecord& line) {
    line.rgb = journal_name(job);
    line.used = out.exposure;
    if (controller()) m_next = next_exposure(m_model, out);
    line.next = m_next;
}

void CameraFrames::written(const ExposureRecord& line) const {
    for (const std::string& journal : m_journals) append_exposure_journal(journal, line);
}

}  // namespace deepsea
