// EXR through OpenEXR, with its own thread pool.

#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfThreading.h>

#include <algorithm>
#include <mutex>
#include <thread>
#include <utility>

#include "codec_files.h"
#include "deepsea/core/atomic_file.h"
#include "deepsea/core/error.h"
#include "exr_zip.h"
#include "fast_codecs.h"
#include "file_checks.h"

namespace deepsea::io_detail {

namespace {

/// OpenEXR's global thread pool, sized once to the cores (it is separate from TBB's: its
/// threads mostly wait on zlib/PIZ work of one file at a time).
int exr_threads() {
    static std::once_flag once;
    static int n = 1;
    std::call_once(once, [] {
        n = int(std::max(1u, std::min(4u, std::thread::hardware_concurrency())));
        if (Imf::globalThreadCount() < n) Imf::setGlobalThreadCount(n);
    });
    return n;
}

}  // namespace

void write_exr(const std::string& path, int width, int height,
               const std::vector<ExrChannel>& channels, bool half, const std::string& compression,
               const ImageMetadata& meta) {
    const int threads = exr_threads();
    Imf::Header header(width, height);
    header.compression() = compression == "piz" ? Imf::PIZ_COMPRESSION : Imf::ZIP_COMPRESSION;
    for (const auto& [name, value] : meta) header.insert(name, Imf::StringAttribute(value));
    Imf::FrameBuffer fb;
    const std::size_t n = std::size_t(width) * height, nc = channels.size();
    // Float channels are written straight from the caller's images; half ones from one
    // interleaved half copy (OpenEXR's writer does not convert float slices to half).
    thread_local std::vector<Imath::half> halves;
    if (half) halves.resize(n * nc);
    for (std::size_t k = 0; k < nc; ++k) {
        const ExrChannel& c = channels[k];
        header.channels().insert(c.name, Imf::Channel(half ? Imf::HALF : Imf::FLOAT));
        if (half) {
            Imath::half* h = halves.data() + k;
            for (std::size_t i = 0; i < n; ++i) h[i * nc] = Imath::half(c.base[i * c.stride]);
            fb.insert(c.name,
                      Imf::Slice(Imf::HALF, reinterpret_cast<char*>(h), sizeof(Imath::half) * nc,
                                 sizeof(Imath::half) * nc * std::size_t(width)));
        } else {
            fb.insert(c.name,
                      Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(const_cast<float*>(c.base)),
                                 sizeof(float) * c.stride,
                                 sizeof(float) * c.stride * std::size_t(width)));
        }
    }
    write_atomically(path, [&](const std::string& tmp) {
        exr_call(path, [&] {
            Imf::OutputFile out(tmp.c_str(), header, threads);
            out.setFrameBuffer(fb);
            out.writePixels(height);
        });
    });
}

struct ExrReader::Impl {
    std::unique_ptr<Imf::InputFile> file;
    int x0 = 0, y0 = 0;
};

ExrReader::ExrReader(const std::string& path) : m_impl(new Impl), m_path(path) {
    require_readable(path);
    check_exr_header(path);
    exr_call(path,
             [&] { m_impl->file = std::make_unique<Imf::InputFile>(path.c_str(), exr_threads()); });
    const Imf::Header& h = m_impl->file->header();
    const auto& dw = h.dataWindow();
    const long long w = (long long)dw.max.x - dw.min.x + 1, hh = (long long)dw.max.y - dw.min.y + 1;
    int n = 0;
    for (auto it = h.channels().begin(); it != h.channels().end(); ++it) {
        m_channels.push_back(it.name());
        m_float.push_back(it.channel().type != Imf::UINT);
        ++n;
        if (n > kMaxImageChannels) break;
    }
    check_image_size(w, hh, n, path);
    // OpenEXR lists channels alphabetically; OpenImageIO (and so deepsea's messages until
    // now) lists each layer's R, G, B, A first: keep that order.
    const auto rank = [](const std::string& name) {
        const std::size_t dot = name.rfind('.');
        const std::string suffix = dot == std::string::npos ? name : name.substr(dot + 1);
        static const char* order[] = {"R", "G", "B", "A"};
        for (int i = 0; i < 4; ++i)
            if (suffix == order[i]) return i;
        return 4;
    };
    const auto layer = [](const std::string& name) {
        const std::size_t dot = name.rfind('.');
        return dot == std::string::npos ? std::string() : name.substr(0, dot);
    };
    std::vector<std::size_t> idx(m_channels.size());
    for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = i;
    // Ties keep the file's order. Not std::stable_sort: under clang 14 + ASan its temporary
    // buffer (libstdc++ 12) is reported as an alloc-dealloc mismatch.
    std::sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) {
        const std::string la = layer(m_channels[a]), lb = layer(m_channels[b]);
        if (la != lb) return la < lb;
        const int ra = rank(m_channels[a]), rb = rank(m_channels[b]);
        return ra != rb ? ra < rb : a < b;
    });
    std::vector<std::string> names;
    std::vector<bool> floats;
    for (std::size_t i : idx) names.push_back(m_channels[i]), floats.push_back(m_float[i]);
    m_channels = std::move(names);
    m_float = std::move(floats);
    m_width = int(w);
    m_height = int(hh);
    m_impl->x0 = dw.min.x;
    m_impl->y0 = dw.min.y;
}

ExrReader::~ExrReader() = default;

void ExrReader::read(const std::vector<int>& channels, float* dst) {
    static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "EXR samples are little-endian");
#if DEEPSEA_EXR_OWN_ZIP
    std::vector<std::string> names;
    for (const int c : channels) names.push_back(m_channels[c]);
    if (read_zip_floats(*m_impl->file, m_path, names, m_width, m_height, m_impl->y0, dst)) return;
#endif
    const std::size_t w = std::size_t(m_width), nc = channels.size();
    Imf::FrameBuffer fb;
    for (std::size_t c = 0; c < nc; ++c) {
        // The frame buffer's origin is the data window's, so that dst holds it from its first
        // pixel.
        char* base = reinterpret_cast<char*>(dst + c - std::ptrdiff_t(nc) * m_impl->x0 -
                                             std::ptrdiff_t(nc * w) * m_impl->y0);
        fb.insert(m_channels[channels[c]],
                  Imf::Slice(Imf::FLOAT, base, sizeof(float) * nc, sizeof(float) * nc * w));
    }
    exr_call(m_path, [&] {
        m_impl->file->setFrameBuffer(fb);
        m_impl->file->readPixels(m_impl->y0, m_impl->y0 + m_height - 1);
    });
}

}  // namespace deepsea::io_detail
