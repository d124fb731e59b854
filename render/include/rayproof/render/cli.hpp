// rayproof/render/cli.hpp — the `render` and `export-pov` subcommands of the rayproof
// program. Running one of them sets `status`: 0 success, 1 failure (a bad scene, a file
// that cannot be read or written); usage errors stop the parse (rayproof/cli.hpp, exit 2).
#pragma once

namespace CLI {
class App;
}

namespace rayproof::render {

void add_commands(CLI::App& app, int& status);

}  // namespace rayproof::render
