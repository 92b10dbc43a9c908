#pragma once
// Internal to batch: a sequence's camera stage (docs/camera.md): the stage for the frames'
// camera (remade when their size changes), the auto-exposure controller's state from frame to
// frame, and its journals (exposure_journal.h) for --resume.

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "deepsea/batch/exposure_journal.h"
#include "deepsea/batch/frame_jobs.h"
#include "deepsea/camera/camera_stage.h"

namespace deepsea {

class CameraFrames {
public:
    /// `manifests`: the sequence's manifest paths (the journals lie beside them). A fresh run
    /// (not `resume`) removes the journals of an earlier run there; a resumed one reads them.
    /// `port`: the housing's, whose radiance factor the stage applies (docs/ports.md).
    CameraFrames(const CameraModel& model, const std::optional<Port>& port,
                 const std::vector<std::string>& manifests, bool resume);

    /// True when the auto-exposure controller is on.
    bool controller() const { return m_model.auto_exposure.enabled; }
    /// Resume: whether `job`, whose outputs are complete, may be skipped: always without the
    /// controller, else when the journal holds its settings (others are rendered again, with
    /// the same bits). Reads only what the constructor read (any thread).
    bool can_skip(const FrameJob& job) const;
    /// A skipped frame: the controller continues from its journal line. In frame order.
    void skipped(const FrameJob& job);
    /// Records `radiance` as `job`'s frame into `out` over `camera` (the stage is remade for a
    /// camera of another size), with the controller's settings, and steps the controller. The
    /// frame's journal line goes to `line`. In frame order.
    void record(const Camera& camera, const FrameJob& job, const Image& radiance,
                CameraLayerSet layers, CameraOutput& out, ExposureRecord& line);
    /// Whether frames over `camera` can be recorded row by row (CameraStage::records_rows).
    bool records_rows(const Camera& camera);
    /// record() with the radiance handed over row by row by `render` (CameraStage::apply_rows):
    /// no radiance frame. The same bits. In frame order.
    void record_rows(const Camera& camera, const FrameJob& job,
                     const std::function<void(const CameraStage::RadianceRows&)>& render,
                     CameraLayerSet layers, CameraOutput& out, ExposureRecord& line);
    /// After the frame's outputs are written: appends its line to the journals (controller on).
    void written(const ExposureRecord& line) const;

private:
    /// The stage over `camera`, made again when the camera changes.
    const CameraStage& stage(const Camera& camera);
    /// After a frame is recorded: its journal line, and the controller's step.
    void step(const FrameJob& job, const CameraOutput& out, ExposureRecord& line);

    CameraModel m_model;
    std::optional<Port> m_port;
    std::vector<std::string> m_journals;
    std::map<std::string, ExposureRecord> m_read;  ///< resume: the journal's lines
    std::unique_ptr<CameraStage> m_stage;
    FrameExposure m_next;  ///< the controller's settings for the next frame rendered
};

}  // namespace deepsea
