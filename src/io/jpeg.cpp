// JPEG encoding and decoding through libjpeg-turbo.

// jpeglib.h needs FILE and size_t declared first.
#include <cstdio>
#include <cstdlib>
// clang-format off
#include <jpeglib.h>
// clang-format on

#include <csetjmp>

#include "codec_files.h"
#include "deepsea/core/atomic_file.h"
#include "deepsea/core/error.h"
#include "exif.h"
#include "fast_codecs.h"
#include "file_checks.h"

namespace deepsea::io_detail {

namespace {

/// libjpeg's error manager for one call: an error's message is kept here and the call jumps
/// back (then one IoError names the file); nothing is printed (libjpeg's default
/// output_message writes to stderr).
struct JpegError {
    jpeg_error_mgr mgr;
    std::jmp_buf jump;
    char message[JMSG_LENGTH_MAX] = {};
};

extern "C" void jpeg_error_exit(j_common_ptr cinfo) {
    auto* e = reinterpret_cast<JpegError*>(cinfo->err);
    (*cinfo->err->format_message)(cinfo, e->message);
    std::longjmp(e->jump, 1);
}

extern "C" void jpeg_silent(j_common_ptr, int) {}
extern "C" void jpeg_no_output(j_common_ptr) {}

/// Installs `err` as the error manager of the call: errors jump back, warnings and trace
/// messages go to `emit`, nothing is printed.
jpeg_error_mgr* jpeg_errors(JpegError& err, void (*emit)(j_common_ptr, int)) {
    jpeg_error_mgr* mgr = jpeg_std_error(&err.mgr);
    mgr->error_exit = jpeg_error_exit;
    mgr->emit_message = emit;
    mgr->output_message = jpeg_no_output;
    return mgr;
}

}  // namespace

void write_jpeg(const std::string& path, int width, int height, int channels,
                const std::uint8_t* pixels, const ImageMetadata& meta) {
    std::string comment;
    for (const auto& [name, value] : meta) comment += name + "=" + value + "\n";
    unsigned char* buf = nullptr;
    unsigned long size = 0;
    // Plain C structs only between setjmp and longjmp (no destructors skipped).
    jpeg_compress_struct cinfo{};
    JpegError err;
    cinfo.err = jpeg_errors(err, jpeg_silent);
    if (setjmp(err.jump)) {
        jpeg_destroy_compress(&cinfo);
        std::free(buf);
        io_fail(path, std::string("JPEG encoder: ") + err.message);
    }
    jpeg_create_compress(&cinfo);
    jpeg_mem_dest(&cinfo, &buf, &size);
    cinfo.image_width = JDIMENSION(width);
    cinfo.image_height = JDIMENSION(height);
    cinfo.input_components = channels;
    cinfo.in_color_space = channels == 3 ? JCS_RGB : JCS_GRAYSCALE;
    jpeg_set_defaults(&cinfo);  // 4:2:0, JFIF, Huffman tables of the standard
    jpeg_set_quality(&cinfo, 95, TRUE);
    jpeg_start_compress(&cinfo, TRUE);
    if (comment.size() < 65000) {
        jpeg_write_marker(&cinfo, JPEG_COM, reinterpret_cast<const JOCTET*>(comment.data()),
                          unsigned(comment.size()));
    }
    const std::size_t row = std::size_t(width) * channels;
    while (cinfo.next_scanline < cinfo.image_height) {
        JSAMPROW r = const_cast<JSAMPROW>(pixels + cinfo.next_scanline * row);
        jpeg_write_scanlines(&cinfo, &r, 1);
    }
    jpeg_finish_compress(&cinfo);
    jpeg_destroy_compress(&cinfo);
    try {
        write_atomically(path, [&](const std::string& tmp) { write_bytes(tmp, buf, size, path); });
    } catch (...) {
        std::free(buf);
        throw;
    }
    std::free(buf);
}

namespace {

/// Warnings are errors when decoding: libjpeg "warns" of a truncated file or damaged data and
/// fills the rest with grey, which would be rendered as if it were the frame.
extern "C" void jpeg_warning_is_error(j_common_ptr cinfo, int level) {
    if (level < 0) jpeg_error_exit(cinfo);
}

}  // namespace

void decode_jpeg_rgb(const std::string& path, int& width, int& height,
                     std::vector<std::uint8_t>& rgb) {
    const auto scratch = decode_scratch.take();  // before setjmp: only C objects after it
    const std::vector<std::uint8_t>& file = scratch->file;
    read_whole_file(path, scratch->file);
    const int orientation = jpeg_orientation(file.data(), file.size());
    if (orientation != 1) {
        throw InputError(path + ": its EXIF orientation " + std::to_string(orientation) + " (" +
                         describe_orientation(orientation) +
                         ") would turn the colour against the depth, which deepsea pairs pixel "
                         "by pixel as stored; store the frame upright (exiftran -ai) or remove "
                         "the tag");
    }
    jpeg_decompress_struct cinfo{};
    JpegError err;
    cinfo.err = jpeg_errors(err, jpeg_warning_is_error);
    // Only C objects between here and the longjmp; the exception is thrown after it.
    long long w = 0, h = 0;
    if (setjmp(err.jump)) {
        jpeg_destroy_decompress(&cinfo);
        io_fail(path, std::string("corrupt or truncated JPEG (") + err.message + ")");
    }
    jpeg_create_decompress(&cinfo);
    jpeg_mem_src(&cinfo, file.data(), static_cast<unsigned long>(file.size()));
    jpeg_read_header(&cinfo, TRUE);
    w = cinfo.image_width;
    h = cinfo.image_height;
    try {
        check_image_size(w, h, 3, path);  // and an ExpectImageSize of the caller's
    } catch (...) {
        jpeg_destroy_decompress(&cinfo);
        throw;
    }
    cinfo.out_color_space = JCS_RGB;  // grey and YCbCr alike; CMYK is refused below
    if (cinfo.jpeg_color_space == JCS_CMYK || cinfo.jpeg_color_space == JCS_YCCK) {
        jpeg_destroy_decompress(&cinfo);
        io_fail(path, "CMYK JPEG is not supported");
    }
    jpeg_start_decompress(&cinfo);
    width = int(w);
    height = int(h);
    rgb.resize(std::size_t(width) * height * 3);
    while (cinfo.output_scanline < cinfo.output_height) {
        JSAMPROW r = rgb.data() + std::size_t(cinfo.output_scanline) * width * 3;
        jpeg_read_scanlines(&cinfo, &r, 1);
    }
    jpeg_finish_decompress(&cinfo);
    jpeg_destroy_decompress(&cinfo);
}

}  // namespace deepsea::io_detail
