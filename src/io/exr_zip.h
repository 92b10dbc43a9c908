#pragma once
// EXR depth maps compressed with ZIP, inflated by libdeflate (private to deepsea_io), for the
// OpenEXR versions that need it. OpenEXR before 3.2 (Debian 12 has 3.1) inflates ZIP blocks
// with zlib, at about half libdeflate's speed, which made reading a float depth map the
// slowest step of a sequence's input; OpenEXR 3.2 and later inflate with libdeflate itself.
// So this reader is compiled and used only with OpenEXR < 3.2 (DEEPSEA_EXR_OWN_ZIP); with a
// later OpenEXR, readPixels reads every file. Remove it when deepsea requires OpenEXR 3.2.

#include <OpenEXR/ImfForward.h>
#include <OpenEXR/OpenEXRConfig.h>

#include <string>
#include <vector>

#if OPENEXR_VERSION_MAJOR < 3 || (OPENEXR_VERSION_MAJOR == 3 && OPENEXR_VERSION_MINOR < 2)
#define DEEPSEA_EXR_OWN_ZIP 1
#else
#define DEEPSEA_EXR_OWN_ZIP 0
#endif

#if DEEPSEA_EXR_OWN_ZIP
namespace deepsea::io_detail {

/// A scanline file compressed with ZIP (16 lines a block) or ZIPS (1) whose chosen channels
/// are all 32-bit float, unsampled (a depth map as deepsea and most renderers write it): its
/// blocks are read raw through OpenEXR and inflated by libdeflate in parallel, then undone as
/// OpenEXR's zip compressor does them (a byte predictor, then the two halves interleaved).
/// Returns false, having read nothing, for every other file (OpenEXR's readPixels reads those).
/// Reads channels `names` of rows y0 .. y0 + height - 1, interleaved, into `dst`; IoError naming
/// `path`.
bool read_zip_floats(Imf::InputFile& file, const std::string& path,
                     const std::vector<std::string>& names, int width, int height, int y0,
                     float* dst);

}  // namespace deepsea::io_detail
#endif
