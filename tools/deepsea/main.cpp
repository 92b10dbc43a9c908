// deepsea: one CLI, a table of subcommands (commands.h). main parses, dispatches, and maps
// deepsea::Error to one line on stderr and a non-zero exit code; usage errors (an unknown
// command or option, a missing or bad value) are one line and exit code 2, as config errors.

#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <new>
#include <string>

#include "cli_util.h"
#include "commands.h"
#include "deepsea/core/error.h"

int main(int argc, char** argv) {
    deepsea::cli::exit_on_signals();  // 130 on SIGINT/SIGTERM in every command
    CLI::App app{
        "deepsea: deep-sea camera simulator (RGB-D in, deep-sea frames out); `deepsea help "
        "COMMAND` or `deepsea COMMAND --help` lists a command's options"};
    app.name("deepsea");               // "Usage: deepsea render", also for `deepsea help render`
    deepsea::cli::add_verbosity(app);  // `deepsea -q render ...` as `deepsea render -q ...`
    app.set_version_flag("--version", std::string("deepsea ") + DEEPSEA_VERSION);
    app.require_subcommand(1);
    // A repeated option takes its last value, as in most Unix tools (scripts append overrides).
    // --help shows every option's default. Both apply to the subcommands added below.
    app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    app.option_defaults()->always_capture_default();
    for (const auto& cmd : deepsea::cli::kCommands) {
        CLI::App* sub = app.add_subcommand(cmd.name, cmd.help);
        cmd.setup(*sub);
        deepsea::cli::add_verbosity(*sub);
    }
    // `deepsea help [COMMAND]`: the same text as --help (not a subcommand: it computes nothing).
    if (argc >= 2 && std::string(argv[1]) == "help") {
        if (argc == 2) {
            std::fputs(app.help().c_str(), stdout);
            return 0;
        }
        const std::string name = argv[2];
        for (CLI::App* sub : app.get_subcommands({})) {
            if (sub->get_name() == name && argc == 3) {
                std::fputs(sub->help("deepsea").c_str(), stdout);
                return 0;
            }
        }
        std::fprintf(stderr, "deepsea: error: help: %s (see deepsea --help)\n",
                     argc == 3 ? ("unknown command '" + deepsea::one_line(name, 200) + "'").c_str()
                               : "expected one command name");
        return 2;
    }
    // An empty argument is an unset shell variable far more often than a wish (`--shard ''`
    // would bake the whole library, `--rgb ''` name no file): a usage error naming the option.
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        const std::size_t eq = arg.find('=');
        const bool empty_inline = arg.rfind("--", 0) == 0 && eq == arg.size() - 1;
        if (!arg.empty() && !empty_inline) continue;
        const std::string option = empty_inline ? arg.substr(0, eq)
                                   : i > 1 && argv[i - 1][0] == '-'
                                       ? std::string(argv[i - 1])
                                       : "argument " + std::to_string(i);
        std::fprintf(stderr,
                     "deepsea: error: %s: an empty value (an unset shell variable?); give a "
                     "value or leave the option out\n",
                     deepsea::one_line(option, 200).c_str());
        return 2;
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
        return deepsea::OutOfMemory("").exit_code();
    } catch (const std::filesystem::filesystem_error& e) {
        // A path the system refuses (too long, a loop of links): the path and the reason, as
        // every other file error.
        const std::string path = e.path1().empty() ? std::string("a path") : e.path1().string();
        std::fprintf(stderr, "deepsea: error: %s: %s\n", deepsea::one_line(path, 300).c_str(),
                     e.code().message().c_str());
        return deepsea::IoError("").exit_code();
    } catch (const deepsea::Error& e) {
        std::fprintf(stderr, "deepsea: error: %s\n", deepsea::one_line(e.what(), 1000).c_str());
        return e.exit_code();
    } catch (const std::exception& e) {
        std::fprintf(stderr, "deepsea: error: %s\n", deepsea::one_line(e.what(), 1000).c_str());
        return 1;
    }
    return 0;
}
