// deepsea: one CLI, a table of subcommands (commands.h). main parses, dispatches, and maps
// deepsea::Error to one line on stderr and a non-zero exit code; usage errors (an unknown
// command or option, a missing or bad value) are one line and exit code 2, as config errors.

#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <new>
#include <string>

#include "commands.h"
#include "deepsea/core/error.h"

int main(int argc, char** argv) {
    CLI::App app{"deepsea: deep-sea camera simulator (RGB-D in, deep-sea frames out)"};
    app.set_version_flag("--version", std::string("deepsea ") + DEEPSEA_VERSION);
    app.require_subcommand(1);
    // A repeated option takes its last value, as in most Unix tools (scripts append overrides).
    // --help shows every option's default. Both apply to the subcommands added below.
    app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    app.option_defaults()->always_capture_default();
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
        // One line, like every other error, and the exit code of a config error (CLI11's own
        // codes, 104-109, mean nothing to a caller).
        std::string what = e.what();
        std::string help = "deepsea --help";
        if (app.get_subcommands().empty() && argc > 1 && argv[1][0] != '-') {
            what = std::string("unknown command '") + argv[1] + "'";
        } else if (!app.get_subcommands().empty()) {
            help = "deepsea " + app.get_subcommands().front()->get_name() + " --help";
        }
        std::fprintf(stderr, "deepsea: error: %s (see %s)\n", deepsea::one_line(what, 1000).c_str(),
                     help.c_str());
        return 2;  // ConfigError's code
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
