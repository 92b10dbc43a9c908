#pragma once
/// \file Files a command reads, checked before a byte is read: they exist, are regular files
/// (not a device such as /dev/zero, a pipe or a folder, which never end or are no file) and
/// are no larger than what deepsea reads of their kind; and text read with that bound.

#include <cstdint>
#include <string>

namespace deepsea {

/// Largest config, manifest or other text file deepsea reads: a setup is a few kilobytes, a
/// library manifest or sequence manifest a few hundred.
inline constexpr std::uintmax_t kMaxTextFileBytes = 16u << 20;
/// Largest image file deepsea reads: a 100-megapixel float RGBA EXR, uncompressed, is 1.6 GB.
inline constexpr std::uintmax_t kMaxImageFileBytes = std::uintmax_t(4) << 30;

/// IoError "`path`: problem" unless `path` names an existing regular file (a link to one is
/// fine) of at most `max_bytes` that this process may read; `what` says what the file is for
/// ("a YAML file", "an image"), for the folder and size messages. An empty path or one holding
/// a NUL character is an IoError too.
void require_input_file(const std::string& path, std::uintmax_t max_bytes, const std::string& what);

/// The bytes of `path`, after require_input_file(path, max_bytes, what); reads at most
/// max_bytes (a file that grows meanwhile is refused, not followed).
std::string read_text_file(const std::string& path, const std::string& what,
                           std::uintmax_t max_bytes = kMaxTextFileBytes);

}  // namespace deepsea
