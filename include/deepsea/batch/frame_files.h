#pragma once
/// \file One frame's files: reading its inputs into a Frame, writing its outputs (FrameWriter,
/// which owns how the exposed image is encoded), and whether a finished run left them whole.
/// A sequence's frame reaches io through these only.

#include <string>
#include <utility>

#include "deepsea/batch/frame_jobs.h"
#include "deepsea/batch/layer_files.h"
#include "deepsea/core/frame.h"
#include "deepsea/io/image_io.h"
#include "deepsea/runtime/layers.h"

namespace deepsea {

/// Reads the job's depth, then its colour (held to the depth's size before it is decoded), into
/// the frame's buffers: a frame of the same size allocates nothing, and PNG or JPEG colour stays
/// as its codes (the compositor decodes them a row at a time). InputError or IoError naming the
/// files.
void read_frame(const FrameJob& job, const DepthReadOptions& depth, Frame& frame);

/// True when the job's outputs are there and whole: each non-empty and decoding fully (the
/// layer file's first layer, the image to its last byte). A kill never leaves a partial file
/// under the final name (writes are atomic), but a 0-byte or damaged file may come from
/// elsewhere; such a frame is rendered again.
bool outputs_complete(const FrameJob& job, const LayerOutput& layers);

/// The outputs of one frame at a time: the layer file, and the exposed image, encoded as the
/// compositor finishes its rows where it can (PNG and JPEG once the exposure is known, with no
/// layer file), else from the final layer. With a camera stage (LayerOutput::camera) the image
/// is the camera's display values and the layer file also holds its layers. Keeps its buffers
/// between frames.
class FrameWriter {
public:
    FrameWriter(int bits, LayerOutput layers) : m_bits(bits), m_layers(std::move(layers)) {}

    /// The layers the renderer must fill for `job`: all the layer file names, or the image's.
    LayerSet layer_set(const FrameJob& job) const;
    /// True when `job`'s image can be encoded row by row (streaming_rows) at `exposure` (0:
    /// not yet known): never with a camera stage, which needs the whole radiance.
    bool streams(const FrameJob& job, double exposure) const;
    /// The rows callback that encodes a width x height image for `job` times `exposure`.
    FinalRows streaming_rows(const FrameJob& job, int width, int height, double exposure);
    /// After a whole render: keeps what writing `job`'s image needs from `layers` (codes, or a
    /// float copy of an image-only job's final layer; a job with a layer file writes from its
    /// own layers).
    void keep(const FrameJob& job, const Layers& layers, double exposure);
    /// Writes `job`'s layer file from `layers` and its image from what was kept, with `meta`,
    /// atomically. IoError naming the file.
    void write(const FrameJob& job, const Layers& layers, const ImageMetadata& meta,
               double exposure) const;
    /// With a camera stage: the camera layers `job` needs (its layer file's), and the image as
    /// 8-bit codes where its file stores them (an 8-bit PNG, a JPEG).
    CameraLayerSet camera_set(const FrameJob& job) const;
    /// With a camera stage: the layer file from `layers` and `recorded`'s layers, the image
    /// from `recorded.codes8` (lent to the encoder, not copied; given back) or `recorded.image`
    /// (display values, write_display), with `meta`, atomically.
    void write(const FrameJob& job, const Layers& layers, CameraOutput& recorded,
               const ImageMetadata& meta) const;

private:
    int m_bits;
    LayerOutput m_layers;
    EncodedImage m_codes;  ///< the image's codes (PNG, JPEG)
    Image m_final;         ///< the final layer of an image-only job, for other formats
};

}  // namespace deepsea
