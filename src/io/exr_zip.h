#pragma once
// EXR depth maps compressed with ZIP, inflated by libdeflate (private to deepsea_io).

#include <OpenEXR/ImfForward.h>

#include <string>
#include <vector>

namespace deepsea::io_detail {

/// A scanline file compressed with ZIP (16 lines a block) or ZIPS (1) whose chosen channels
/// are all 32-bit float, unsampled (a depth map as deepsea and most renderers write it): its
/// blocks are read raw through OpenEXR and inflated by libdeflate in parallel, then undone as
/// OpenEXR's zip compressor does them (a byte predictor, then the two halves interleaved).
/// OpenEXR 3.1 inflates with zlib, at about half libdeflate's speed. Returns false, having
/// read nothing, for every other file (OpenEXR's readPixels reads those). Reads channels
/// `names` of rows y0 .. y0 + height - 1, interleaved, into `dst`; IoError naming `path`.
bool read_zip_floats(Imf::InputFile& file, const std::string& path,
                     const std::vector<std::string>& names, int width, int height, int y0,
                     float* dst);

}  // namespace deepsea::io_detail
