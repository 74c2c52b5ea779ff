#pragma once
// --help shows the options a user sets, in a few sections of their own; --help-all shows
// every option, grouped as declared. Options left out of --help are in force all the same,
// on the command line and in --config files.

#include <CLI/CLI.hpp>
#include <string>
#include <utility>
#include <vector>

namespace f2c::app {

// A section of --help: its title and its options' long names (without dashes), in order.
struct HelpSection {
  std::string title;
  std::vector<std::string> options;
};

class EverydayHelp : public CLI::Formatter {
 public:
  explicit EverydayHelp(std::vector<HelpSection> sections) : sections_(std::move(sections)) {}

  std::string make_help(const CLI::App* app, std::string name, CLI::AppFormatMode mode) const override {
    if (mode == CLI::AppFormatMode::All) return CLI::Formatter::make_help(app, std::move(name), mode);
    std::string out = make_description(app) + make_usage(app, name) + make_positionals(app);
    size_t shown = 0;
    for (const HelpSection& section : sections_) {
      std::vector<const CLI::Option*> opts;
      for (const std::string& lname : section.options) {
        const CLI::Option* opt = app->get_option_no_throw("--" + lname);
        if (opt != nullptr) opts.push_back(opt);
      }
      shown += opts.size();
      if (!opts.empty()) out += make_group(section.title, false, opts);
    }
    const size_t all = app->get_options([](const CLI::Option* o) { return o->nonpositional(); }).size();
    out += "\n" + std::to_string(all - shown) + " more options, grouped: " + app->get_name() +
           " --help-all (each also a key of a --config file)\n";
    return out;
  }

 private:
  std::vector<HelpSection> sections_;
};

}  // namespace f2c::app
