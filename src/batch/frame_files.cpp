#include "deepsea/batch/frame_files.h"

#include <filesystem>

#include "deepsea/core/error.h"

namespace deepsea {

namespace fs = std::filesystem;

namespace {

/// One output written whole (empty path: none wanted).
bool complete(const std::string& path, const LayerOutput* layers) {
    if (path.empty()) return true;
    std::error_code ec;
    if (!fs::is_regular_file(path, ec) || fs::file_size(path, ec) == 0 || ec) return false;
    try {
        if (layers) {
            // The first layer written decodes: every channel of a scanline file is in each of
            // its line blocks, so the last block decoding means the file is whole.
            const std::string& first = layers->names.front();
            (void)read_exr_layer(path, first,
                                 first == "depth"    ? std::vector<std::string>{"Z"}
                                 : first == "normal" ? std::vector<std::string>{"X", "Y", "Z"}
                                                     : std::vector<std::string>{"R", "G", "B"});
        } else {
            // A PNG cut short by its last chunk still decodes every row.
            if (!image_file_ends(path)) return false;
            (void)read_color(path);
        }
        return true;
    } catch (const Error&) {
        return false;
    }
}

}  // namespace

void read_frame(const FrameJob& job, const DepthReadOptions& depth, Frame& frame) {
    read_depth(job.depth, frame.depth, depth);
    {
        const ExpectImageSize same(frame.depth.width, frame.depth.height,
                                   job.rgb + " and " + job.depth);
        read_frame_color(job.rgb, frame);
    }
    require_same_size(frame.color_width(), frame.color_height(), frame.depth.width,
                      frame.depth.height, job.rgb + " and " + job.depth);
}

bool outputs_complete(const FrameJob& job, const LayerOutput& layers) {
    return complete(job.output, nullptr) && complete(job.layers, &layers);
}

LayerSet FrameWriter::layer_set(const FrameJob& job) const {
    return job.layers.empty() ? LayerSet::Final : m_layers.compositor_set();
}

bool FrameWriter::streams(const FrameJob& job, double exposure) const {
    return !m_layers.camera && job.layers.empty() && exposure != 0.0 && !job.output.empty() &&
           writes_encoded(job.output);
}

FinalRows FrameWriter::streaming_rows(const FrameJob& job, int width, int height, double exposure) {
    prepare_encoded(width, height, 3, m_bits, job.output, m_codes);
    return [this, width, exposure](int v, const float* rgb) {
        const std::size_t n = 3 * std::size_t(width);
        encode_srgb_samples(rgb, n, exposure, n * std::size_t(v), m_codes);
    };
}

void FrameWriter::keep(const FrameJob& job, const Layers& layers, double exposure) {
    if (job.output.empty() || !job.layers.empty()) return;
    if (writes_encoded(job.output)) {
        encode_srgb(layers.final, exposure, m_bits, job.output, m_codes);
    } else {
        m_final = layers.final;
    }
}

void FrameWriter::write(const FrameJob& job, const Layers& layers, const ImageMetadata& meta,
                        double exposure) const {
    if (!job.layers.empty()) write_layers(job.layers, layers, meta, m_layers);
    if (job.output.empty()) return;
    // The exposure is applied while encoding (no exposed copy).
    if (job.layers.empty() && writes_encoded(job.output)) {
        write_encoded(job.output, m_codes, meta);
    } else {
        write_color(job.output, job.layers.empty() ? m_final : layers.final, m_bits, meta,
                    exposure);
    }
}

void FrameWriter::write(const FrameJob& job, const Layers& layers, CameraOutput& recorded,
                        const ImageMetadata& meta) const {
    if (!job.layers.empty()) write_layers(job.layers, layers, meta, m_layers, &recorded);
    if (job.output.empty()) return;
    if (recorded.codes8.empty()) return write_display(job.output, recorded.image, m_bits, meta);
    thread_local EncodedImage codes;  // its storage kept from frame to frame
    prepare_encoded(recorded.width, recorded.height, 3, 8, job.output, codes);
    // The codes lent to the encoder and given back, also on a throw (not copied: 1.9 MB at
    // 800 x 800).
    struct Lend {
        std::vector<std::uint8_t>&a, &b;
        ~Lend() { a.swap(b); }
    } lend{codes.codes8, recorded.codes8};
    codes.codes8.swap(recorded.codes8);
    write_encoded(job.output, codes, meta);
}

CameraLayerSet FrameWriter::camera_set(const FrameJob& job) const {
    CameraLayerSet set = job.layers.empty() ? CameraLayerSet{} : m_layers.camera_set();
    // prepare_encoded's rule: a PNG has the writer's bits, a JPEG 8.
    set.codes8 = !job.output.empty() && writes_encoded(job.output) &&
                 (m_bits == 8 || image_format(job.output) == "jpg");
    return set;
}

}  // namespace deepsea
