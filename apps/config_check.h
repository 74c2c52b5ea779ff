#pragma once
// What CLI11's TOML/INI reader lets pass but a config file must not say: the same key twice
// (in one section, in a repeated section, or once dotted at the top and once in its section:
// which one won was not said), a key without a value (read as 0 or ""), and a string or list
// that is never closed (read as its raw text: an output folder named `"o/...`).

#include <filesystem>

namespace f2c::app {

// InputError "FILE:LINE: what" for the first such line; a file that cannot be read is left
// to CLI11, which says so.
void CheckConfigFile(const std::filesystem::path& path);

}  // namespace f2c::app
