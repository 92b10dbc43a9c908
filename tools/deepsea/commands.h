#pragma once
/// \file The subcommand table. Each cmd_<name>.cpp defines one setup function that adds its
/// options to a CLI11 subcommand and sets a callback; callbacks throw deepsea::Error.

#include <CLI/CLI.hpp>

namespace deepsea::cli {

struct Command {
    const char* name;
    const char* help;
    void (*setup)(CLI::App& sub);
};

// One per file, in the order `deepsea --help` lists them.
void setup_scene(CLI::App& sub);
void setup_reference(CLI::App& sub);
void setup_render(CLI::App& sub);
void setup_merge_shards(CLI::App& sub);
void setup_bake(CLI::App& sub);
void setup_info(CLI::App& sub);
void setup_bake_library(CLI::App& sub);
void setup_import_config(CLI::App& sub);
void setup_bench(CLI::App& sub);
void setup_demo(CLI::App& sub);

inline const Command kCommands[] = {
    {"scene", "generate a procedural RGB-D seafloor flight (PNG + depth EXR pairs)", setup_scene},
    {"reference", "exact per-pixel rendering without an asset (ground truth)", setup_reference},
    {"bake", "bake the backscatter asset of a camera x rig x water", setup_bake},
    {"bake-library", "bake a manifest of cameras x rigs x waters (shardable)", setup_bake_library},
    {"info", "show an asset's camera, rig, water, lattice and values", setup_info},
    {"import-config", "convert a DeepSeaRenderer config into deepsea YAML", setup_import_config},
    {"render", "composite frames or sequences with a baked asset", setup_render},
    {"merge-shards", "check a sharded render's parts and write its one manifest",
     setup_merge_shards},
    {"bench", "time the compositor and a sequence render", setup_bench},
    {"demo", "the embedded default: scene, asset, rendered flight, contact sheet", setup_demo},
};

}  // namespace deepsea::cli
