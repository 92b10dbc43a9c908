#include "deepsea/batch/shard_merge.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <regex>

#include "deepsea/batch/frame_jobs.h"
#include "deepsea/core/atomic_file.h"
#include "deepsea/core/error.h"
#include "deepsea/core/folder_lock.h"
#include "deepsea/io/image_io.h"

namespace deepsea {

namespace fs = std::filesystem;

namespace {

std::string list(const std::vector<std::string>& items) {
    std::string out;
    const std::size_t shown = std::min<std::size_t>(items.size(), 5);
    for (std::size_t i = 0; i < shown; ++i) out += (i ? ", " : "") + items[i];
    if (items.size() > shown) out += " and " + std::to_string(items.size() - shown) + " more";
    return out;
}

/// The shard manifests in `folder`, by file name.
std::map<std::string, SequenceManifest> read_shards(const std::string& folder) {
    static const std::regex name(R"(deepsea-sequence\.shard-[0-9]+-of-[0-9]+\.json)");
    std::map<std::string, SequenceManifest> shards;
    for (const auto& entry : fs::directory_iterator(folder)) {
        const std::string file = entry.path().filename().string();
        if (!std::regex_match(file, name)) continue;
        SequenceManifest m = read_manifest(entry.path().string());
        if (!m.shard || shard_manifest_name(m.shard->index, m.shard->count) != file)
            throw InputError(entry.path().string() + ": its shard record does not match its name");
        shards.emplace(file, std::move(m));
    }
    return shards;
}

/// One output written and whole as far as a cheap look tells: a file, non-empty, and (PNG,
/// JPEG) ending as its format ends. Every shard verified its own outputs as it wrote them.
bool present(const std::string& path, bool image) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec) || fs::file_size(path, ec) == 0 || ec) return false;
    return !image || image_file_ends(path);
}

}  // namespace

ShardMerge merge_shards(const std::string& folder, bool check_only) {
    if (!fs::is_directory(folder)) throw IoError(folder + ": not a folder");
    const FolderLock lock(folder);  // no shard renders here now, and no other merge
    const std::map<std::string, SequenceManifest> shards = read_shards(folder);
    const std::string merged_path = (fs::path(folder) / kManifestName).string();
    if (shards.empty()) {
        throw InputError(folder + ": no shard manifests (deepsea-sequence.shard-*.json) to merge" +
                         (fs::exists(merged_path)
                              ? "; " + std::string(kManifestName) + " is there: merged already?"
                              : std::string()));
    }
    // One count, every shard, each finished, all alike.
    const auto& [first_name, first] = *shards.begin();
    const int count = first.shard->count;
    std::vector<bool> seen(std::size_t(count), false);
    std::vector<std::string> unfinished;
    long frames = 0;
    for (const auto& [file, m] : shards) {
        if (m.shard->count != count)
            throw ConfigError(folder + ": " + first_name + " and " + file +
                              " are shards of different counts; remove the shards of the "
                              "other run");
        const std::string diff = first_difference(first, m, {"shard", "frames"});
        if (!diff.empty() || m.shard->sequence_frames != first.shard->sequence_frames ||
            m.shard->image_folder != first.shard->image_folder ||
            m.shard->layers_folder != first.shard->layers_folder)
            throw ConfigError(folder + ": shards " + std::to_string(first.shard->index) + " and " +
                              std::to_string(m.shard->index) + " differ in " +
                              (diff.empty() ? "the sequence (frames or output folders)" : diff) +
                              "; render them again alike (--exposure FACTOR fixes the exposure)");
        seen[std::size_t(m.shard->index)] = true;
        frames += m.frames_total;
        if (m.frames_done != m.frames_total)
            unfinished.push_back(std::to_string(m.shard->index) + " (" +
                                 std::to_string(m.frames_done) + " of " +
                                 std::to_string(m.frames_total) + " frames)");
    }
    std::vector<std::string> missing;
    for (int i = 0; i < count; ++i)
        if (!seen[std::size_t(i)]) missing.push_back(std::to_string(i));
    const std::string of = " of " + std::to_string(count);
    if (!missing.empty())
        throw FramesFailed(folder + ": shard(s) " + list(missing) + of +
                           " have no manifest here: render them (--shard i/" +
                           std::to_string(count) + "), then merge again");
    if (!unfinished.empty())
        throw FramesFailed(folder + ": shard(s) " + list(unfinished) + of +
                           " are not finished: run them again with --resume, then merge again");
    const int sequence_frames = first.shard->sequence_frames;
    if (frames != sequence_frames)
        throw InputError(folder + ": the shards hold " + std::to_string(frames) + " frames, not " +
                         "the sequence's " + std::to_string(sequence_frames));

    // Every frame's outputs that belong in this folder.
    const fs::path here = resolved_path(folder);
    const bool image = first.image && !first.shard->image_folder.empty() &&
                       resolved_path(first.shard->image_folder) == here;
    const bool layers = first.layers && !first.shard->layers_folder.empty() &&
                        resolved_path(first.shard->layers_folder) == here;
    if (!image && !layers)
        throw InputError(folder + ": the shards wrote into '" + first.shard->image_folder +
                         "' and '" + first.shard->layers_folder + "', not here");
    const std::vector<FrameJob> jobs = frame_jobs(
        {first.rgb, first.depth, image ? folder : "", layers ? folder : "", first.image_format});
    if (long(jobs.size()) != sequence_frames)
        throw InputError(folder + ": '" + first.rgb + "' and '" + first.depth + "' pair into " +
                         std::to_string(jobs.size()) + " frames now, " +
                         std::to_string(sequence_frames) + " when the shards rendered them");
    std::vector<std::string> absent;
    for (const FrameJob& j : jobs) {
        if (image && !present(j.output, true)) absent.push_back(j.output);
        if (layers && !present(j.layers, false)) absent.push_back(j.layers);
    }
    if (!absent.empty())
        throw FramesFailed(folder + ": " + std::to_string(absent.size()) +
                           " output(s) missing, empty or cut short: " + list(absent) +
                           "; run their shard again with --resume");

    ShardMerge result;
    result.shards = count;
    result.frames = sequence_frames;
    result.manifest = merged_path;
    result.merged = first;
    result.merged.shard.reset();
    result.merged.frames_total = result.merged.frames_done = sequence_frames;
    if (fs::exists(merged_path))
        check_same_inputs(read_manifest(merged_path), result.merged, merged_path);
    if (check_only) return result;
    write_manifest(merged_path, result.merged);
    for (const auto& [file, m] : shards) fs::remove(fs::path(folder) / file);
    return result;
}

}  // namespace deepsea
