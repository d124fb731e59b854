// rayproof — the command-line program: subcommand dispatch.
#include <cstdio>
#include <cstring>

#ifdef RAYPROOF_HAVE_RENDER
#include <rayproof/render/cli.hpp>
#endif

int rayproof_cli_showcase(int argc, char** argv);

namespace {
struct Command {
    const char* name;
    int (*run)(int, char**);
    const char* help;
};
const Command commands[] = {
    {"showcase", rayproof_cli_showcase, "a table of showcase rays answered by every shape and mode"},
#ifdef RAYPROOF_HAVE_RENDER
    {"render", rayproof_cli_render, "render a scene file (rayproof render SCENE.json -o out.png; --help)"},
    {"export-pov", rayproof_cli_export_pov, "print a scene file as a POV-Ray 3.7 scene"},
#endif
};

int usage(std::FILE* f) {
    std::fprintf(f, "usage: rayproof COMMAND [ARGS...]\n\ncommands:\n");
    for (const Command& c : commands) std::fprintf(f, "  %-12s %s\n", c.name, c.help);
    return f == stdout ? 0 : 2;
}
}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) return usage(stderr);
    if (!std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h") || !std::strcmp(argv[1], "help"))
        return usage(stdout);
    for (const Command& c : commands)
        if (!std::strcmp(argv[1], c.name)) return c.run(argc - 1, argv + 1);
    std::fprintf(stderr, "rayproof: unknown command '%s'\n\n", argv[1]);
    return usage(stderr);
}
