#pragma once
/// \file Write-then-rename: no reader ever sees a half-written output.

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace deepsea {

/// Writes `path` atomically: write(tmp) fills a temporary file beside it (same folder, so the
/// rename is atomic; same extension, so format-by-extension writers pick the same format), then
/// the temporary is checked to be non-empty and renamed over `path`. On any failure (write
/// throws, the temporary is empty, the rename fails) the temporary is removed; the exception
/// from write propagates, other failures throw IoError naming `path`. The folder must exist and
/// be writable (IoError otherwise, before write is called). A symbolic link at `path` to a
/// regular file is written through (the file it leads to is replaced, the link stays); a link to
/// anything else, and an existing `path` that is not a regular file (a device such as
/// /dev/stdout, a pipe, a folder), is an IoError before write is called.
void write_atomically(const std::string& path,
                      const std::function<void(const std::string& tmp)>& write);

/// write_atomically for a text file: `text` as it is (binary mode), written by write_fully.
void write_text_atomically(const std::string& path, const std::string& text);

/// Creates or truncates `file` and writes all of `bytes`, checking every write, fsync and
/// close: a full disk or a failing device is an IoError naming `name` (the user's path, when
/// `file` is a temporary) and the system's reason, never a silently short file.
void write_fully(const std::string& file, std::string_view bytes, const std::string& name);

/// Throws IoError naming both unless `output` is a different file from each of `others`: an
/// output must never replace what the command reads, nor another of its outputs. An existing
/// output is compared by inode (links and relative paths alike), one still to be written by
/// its canonical path. `others` pairs each path with what it is ("the input --rgb", "the
/// --layers output"); empty paths are skipped.
void require_distinct(const std::string& output,
                      const std::vector<std::pair<std::string, std::string>>& others);

/// True if `a` and `b` name one file, whether or not they exist yet: the same inode if both
/// exist, else the same resolved_path.
bool same_file(const std::string& a, const std::string& b);

/// `path` as the system resolves it: absolute, every existing symbolic link followed, "." and
/// ".." applied (also after missing components: "in/nosuch/.." is "in", as the kernel reaches
/// it once the missing folder is created), no trailing separator. Two paths name the same place
/// exactly when their resolved paths are equal.
std::filesystem::path resolved_path(const std::string& path);

/// Throws IoError naming `path` unless its folder exists and is writable.
void require_writable_folder(const std::string& path);

/// If `file_name` (a name, no folder) is one of write_atomically's temporaries, the name of
/// the file it was to become and the id of the process that wrote it; nullopt otherwise.
struct TemporaryName {
    /// temporary_key of the file name the temporary would have been renamed to (that name
    /// itself unless it is too long to fit in a temporary's name)
    std::string target;
    long pid = 0;  ///< process that wrote it
};
std::optional<TemporaryName> parse_temporary_name(const std::string& file_name);

/// The target a temporary for `file_name` names (TemporaryName::target): `file_name` itself, or
/// for a name too long to carry in a temporary's, its start and a hash of its stem.
std::string temporary_key(const std::string& file_name);

}  // namespace deepsea
