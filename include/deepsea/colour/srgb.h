#pragma once
/// \file The sRGB curve (IEC 61966-2-1) and the integer codes of 8- and 16-bit images: what the
/// image readers decode, the compositor decodes a row at a time, and the writers encode.

#include <cstddef>
#include <cstdint>

namespace deepsea {

/// sRGB transfer functions on one value in [0, 1].
float srgb_to_linear(float v);
float linear_to_srgb(float v);

/// srgb_to_linear(k / codes) for every code k = 0 .. codes, codes = 255 (8 bits) or 65535
/// (16 bits): the table srgb_decode reads, made on first use.
const float* srgb_decode_table(int codes);

/// Decodes n 8-bit (0..255) or 16-bit (0..65535) sRGB codes to linear values, through the
/// same tables as read_color: for images that arrive in memory (the Python module).
void srgb_decode(const std::uint8_t* codes, std::size_t n, float* linear);
void srgb_decode(const std::uint16_t* codes, std::size_t n, float* linear);

/// Encodes n linear values times `exposure` (the product in double, rounded to float once, as
/// apply_exposure rounds it) to the 8- or 16-bit codes OpenImageIO stores for them:
/// int(linear_to_srgb(v) * codes + 0.5f), bit for bit, without a pow per value. Non-finite
/// values and values <= 0 give 0, values >= 1 the top code.
void srgb_encode(const float* linear, std::size_t n, double exposure, std::uint8_t* codes);
void srgb_encode(const float* linear, std::size_t n, double exposure, std::uint16_t* codes);

}  // namespace deepsea
