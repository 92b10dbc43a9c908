// deepsea: one CLI, a table of subcommands (commands.h). main parses, dispatches, and maps
// deepsea::Error to one line on stderr and a non-zero exit code.

#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <new>

#include "commands.h"
#include "deepsea/core/error.h"

int main(int argc, char** argv) {
    CLI::App app{"deepsea: deep-sea camera simulator (RGB-D in, deep-sea frames out)"};
    app.set_version_flag("--version", std::string("deepsea ") + DEEPSEA_VERSION);
    app.require_subcommand(1);
    // A repeated option takes its last value, as in most Unix tools (scripts append overrides).
    app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    for (const auto& cmd : deepsea::cli::kCommands) {
        CLI::App* sub = app.add_subcommand(cmd.name, cmd.help);
        cmd.setup(*sub);
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        // one line, like every other error
        std::fprintf(stderr, "deepsea: error: %s (see --help)\n", e.what());
        return e.get_exit_code();
    } catch (const std::bad_alloc&) {
        // Inputs are size-checked before allocation; this is the last line of defence.
        std::fprintf(stderr,
                     "deepsea: error: out of memory (the inputs or settings need more memory "
                     "than this machine has)\n");
        return 1;
    } catch (const deepsea::Error& e) {
        std::fprintf(stderr, "deepsea: error: %s\n", deepsea::one_line(e.what(), 1000).c_str());
        return e.exit_code();
    } catch (const std::exception& e) {
        std::fprintf(stderr, "deepsea: error: %s\n", deepsea::one_line(e.what(), 1000).c_str());
        return 1;
    }
    return 0;
}
