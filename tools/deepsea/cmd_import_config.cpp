// deepsea import-config: a DeepSeaRenderer (Song et al.) configuration file converted into
// deepsea's camera / rig / water YAML (io/import_config.h does the conversion).

#include <cstdio>

#include "cli_util.h"
#include "commands.h"
#include "deepsea/io/import_config.h"

namespace deepsea::cli {

namespace {

struct ImportArgs {
    std::string input, output;
};

void run(const ImportArgs& a) {
    if (a.output.empty() || a.output == "-") {
        std::fputs(import_config(a.input).c_str(), stdout);
        return;
    }
    import_config(a.input, a.output);
    say("wrote %s\n", a.output.c_str());
}

}  // namespace

void setup_import_config(CLI::App& sub) {
    auto a = std::make_shared<ImportArgs>();
    sub.add_option("config", a->input, "DeepSeaRenderer config (YAML)")->required();
    sub.add_option("-o,--output", a->output,
                   "deepsea setup YAML to write ('-' or none: standard output; a link to a file is "
                   "written through)");
    sub.callback([a] { run(*a); });
}

}  // namespace deepsea::cli
