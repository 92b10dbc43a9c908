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

inline const Command kCommands[] = {
    {"scene", "generate a procedural RGB-D seafloor flight (PNG + depth EXR pairs)", setup_scene},
    {"reference", "exact per-pixel rendering without an asset (ground truth)", setup_reference},
};

}  // namespace deepsea::cli
