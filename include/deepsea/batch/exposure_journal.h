#pragma once
/// \file The auto-exposure journal a sequence keeps beside its frames when a camera stage's
/// auto-exposure controller is on (docs/sequences.md): one JSON line per frame written, with
/// the settings the frame was recorded with and those the controller chose for the frame after
/// it, so that `--resume` continues the controller where it stopped instead of starting over.
/// Appended, never rewritten: a line per frame costs the same at frame 10 as at frame 100000.

#include <map>
#include <string>

#include "deepsea/camera/camera_stage.h"

namespace deepsea {

/// The journal's file name in each output folder, beside the manifest.
inline constexpr const char* kExposureJournalName = "deepsea-exposures.jsonl";

/// One frame's line.
struct ExposureRecord {
    std::string rgb;     ///< the frame's colour file, as the job names it
    FrameExposure used;  ///< what the frame was recorded with
    FrameExposure next;  ///< what the controller chose for the next frame after metering it
};

/// The journal's records by colour file (a later line for the same file wins). A missing file
/// is an empty journal; a last line without its newline (a kill while appending) is ignored.
/// InputError "<path>:<line>: ..." for any other line that is not a record.
std::map<std::string, ExposureRecord> read_exposure_journal(const std::string& path);

/// Appends one line (a single write to a file opened for appending). IoError naming the file.
void append_exposure_journal(const std::string& path, const ExposureRecord& record);

}  // namespace deepsea
