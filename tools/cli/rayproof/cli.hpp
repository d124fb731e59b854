// rayproof/cli.hpp — how every rayproof program reads its command line (CLI11) and
// answers a bad one, so that all of them behave alike:
//   -h, --help     the help of the program, or of the subcommand given, on stdout; exit 0
//   a usage error  (an unknown option, a missing or malformed value) one line
//                  "PROGRAM: MESSAGE" naming the option, then the usage line, on stderr;
//                  exit 2
#pragma once

#include <CLI/CLI.hpp>

#include <cstdlib>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace rayproof::cli {

inline constexpr int usage_error = 2;

// Checks for unsigned options, which CLI11 would otherwise wrap around from a minus sign.
inline const CLI::Validator non_negative(
    [](const std::string& s) { return s.empty() || s[0] != '-' ? std::string() : "expects a number >= 0, got " + s; },
    "");
inline const CLI::Validator positive(
    [](const std::string& s) {
        return s.empty() || (s[0] != '-' && std::strtod(s.c_str(), nullptr) != 0) ? std::string()
                                                                                   : "expects a number > 0, got " + s;
    },
    "");

// The innermost subcommand given on the command line (the program itself if none).
inline const CLI::App& innermost(const CLI::App& app) {
    const CLI::App* a = &app;
    while (!a->get_subcommands().empty()) a = a->get_subcommands().front();
    return *a;
}

// "rayproof render": the program's name and its subcommands'.
inline std::string full_name(const CLI::App& app) {
    std::string name = app.get_name();
    for (const CLI::App* p = app.get_parent(); p; p = p->get_parent()) name = p->get_name() + ' ' + name;
    return name;
}

// Prints what the parse error e calls for; returns the exit status.
inline int report(const CLI::App& app, const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) {  // --help
        std::cout << app.help();
        return 0;
    }
    const CLI::App& at = innermost(app);
    const std::string name = full_name(at);
    // CLI11 checks what is required before what is unknown: name the unknown first.
    const std::vector<std::string> unknown = at.remaining();
    const bool has_subcommands = !at.get_subcommands([](const CLI::App*) { return true; }).empty();
    if (e.get_name() == "RequiredError" && !unknown.empty() && has_subcommands)
        std::cerr << name << ": unknown subcommand " << unknown.front() << '\n';
    else if (e.get_name() == "RequiredError" && !unknown.empty())
        std::cerr << name << ": not expected: " << unknown.front() << "; " << e.what() << '\n';
    else
        std::cerr << name << ": " << e.what() << '\n';
    if (const auto f = std::dynamic_pointer_cast<CLI::Formatter>(at.get_formatter()))
        std::cerr << f->make_usage(&at, name);
    std::cerr << "Run '" << name << " --help' for the options.\n";
    return usage_error;
}

// Parses argv into app (running the callbacks of what it names): nothing when the
// program is to go on, else its exit status.
inline std::optional<int> parse(CLI::App& app, int argc, const char* const* argv) {
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return report(app, e);
    }
    return std::nullopt;
}

}  // namespace rayproof::cli
