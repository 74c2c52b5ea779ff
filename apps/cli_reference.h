#pragma once
// docs/cli.md's reference part, generated from the commands' option declarations (the same
// ones that make --help), so that the page cannot drift from the program: a test compares
// them (tests/cli_reference_test.cc); `fine2coarse cli-reference` prints it.

#include <CLI/CLI.hpp>
#include <string>

namespace f2c::app {

// Markdown: for each subcommand its usage line, description and every option, grouped as
// --help-all groups them, with its default and help.
std::string CliReference(const CLI::App& app);

// The hidden `cli-reference` subcommand, which prints CliReference(*app).
struct Subcommand;
Subcommand AddCliReferenceCommand(CLI::App* app);

}  // namespace f2c::app
