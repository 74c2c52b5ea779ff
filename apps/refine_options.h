#pragma once
// The refinement's command-line options (register's "Refinement" groups): every number of
// RefineOptions, with its default shown in --help.

#include <CLI/CLI.hpp>

#include "f2c/refine/refine.h"

namespace f2c::app {

// Adds the options to `cmd`. Values that need parsing (modes, lists) are checked and stored
// into `options` by the returned function, called after the command line is parsed.
std::function<void()> AddRefineOptions(CLI::App* cmd, RefineOptions* options);

}  // namespace f2c::app
