// deepsea merge-shards: check that the shards of a sequence render agree and that every frame
// is there, then write the sequence's one manifest (docs/sequences.md, "Shards").

#include <cstdio>

#include "cli_util.h"
#include "commands.h"
#include "deepsea/batch/shard_merge.h"

namespace deepsea::cli {

namespace {

struct MergeArgs {
    std::vector<std::string> folders;
    bool check = false;
};

void run(const MergeArgs& a) {
    for (const std::string& folder : a.folders) {
        const ShardMerge m = merge_shards(folder, a.check);
        if (a.check) {
            say("%s: %d shard(s) agree, all %d frame(s) there; nothing written\n", folder.c_str(),
                m.shards, m.frames);
        } else {
            say("%s: %d shard(s), %d frame(s): wrote %s\n", folder.c_str(), m.shards, m.frames,
                m.manifest.c_str());
        }
    }
}

}  // namespace

void setup_merge_shards(CLI::App& sub) {
    auto a = std::make_shared<MergeArgs>();
    sub.add_option("folders", a->folders,
                   "output folders of a sharded render (its -o and/or --layers folders)")
        ->required();
    sub.add_flag("--check", a->check, "check only: write nothing, remove nothing");
    sub.callback([a] { run(*a); });
}

}  // namespace deepsea::cli
