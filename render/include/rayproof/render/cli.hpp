// rayproof/render/cli.hpp — the `render` and `export-pov` subcommands of the rayproof
// program. argv[0] is the subcommand name; the return value is the exit status
// (0 success, 1 failure, 2 usage error).
#pragma once

int rayproof_cli_render(int argc, char** argv);
int rayproof_cli_export_pov(int argc, char** argv);
