#pragma once
/// \file DeepSeaRenderer (Song et al.) configuration files converted into deepsea's camera /
/// rig / water YAML, with a comment on every conversion (docs/import-config.md).

#include <string>

namespace deepsea {

/// The deepsea setup YAML for a DeepSeaRenderer config file. The result is checked to parse as
/// a deepsea setup. ConfigError "file:line: key: problem" for a missing or malformed key, and
/// for a file that is not a DeepSeaRenderer config; IoError if it cannot be read. Keys deepsea
/// does not use are ignored (they are listed in the output's closing comment).
std::string import_config(const std::string& path);

/// Converts `path` and writes the YAML to `output` atomically (write_atomically): on any error
/// nothing is left at `output`.
void import_config(const std::string& path, const std::string& output);

}  // namespace deepsea
