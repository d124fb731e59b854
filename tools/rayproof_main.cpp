// rayproof — the command-line program: one subcommand per task, each with its own --help.
#include <rayproof/cli.hpp>

#ifdef RAYPROOF_HAVE_RENDER
#include <rayproof/render/cli.hpp>
#endif

int rayproof_showcase();

int main(int argc, char** argv) {
    CLI::App app{"The rayproof ray intersection kernel from the command line.", "rayproof"};
    app.require_subcommand(1);
    int status = 0;
    app.add_subcommand("showcase", "a table of showcase rays answered by every shape and mode")->callback([&status] {
        status = rayproof_showcase();
    });
#ifdef RAYPROOF_HAVE_RENDER
    rayproof::render::add_commands(app, status);
#endif
    if (const auto stop = rayproof::cli::parse(app, argc, argv)) return *stop;
    return status;
}
