#include "apps/cli_reference.h"

#include <cstdio>
#include <map>
#include <vector>

#include "apps/commands.h"

namespace f2c::app {
namespace {

// Markdown table cells hold no raw '|' or newline.
std::string Cell(std::string text) {
  std::string out;
  for (char c : text) {
    if (c == '|') {
      out += "\\|";
    } else if (c == '\n') {
      out += ' ';
    } else {
      out += c;
    }
  }
  return out;
}

std::string Names(const CLI::Option& opt) {
  std::string names;
  for (const std::string& s : opt.get_snames()) names += (names.empty() ? "" : ", ") + ("-" + s);
  for (const std::string& l : opt.get_lnames()) names += (names.empty() ? "" : ", ") + ("--" + l);
  return "`" + names + "`";
}

std::string Command(const CLI::App& cmd) {
  std::string out = "## " + cmd.get_name() + "\n\n" + cmd.get_description() + "\n\n";
  std::string positionals;
  for (const CLI::Option* opt : cmd.get_options()) {
    if (opt->get_positional()) positionals += " " + opt->get_name();
  }
  out += "    fine2coarse " + cmd.get_name() + " [OPTIONS]" + positionals + "\n\n";
  // Groups in the order their first option was declared, as --help-all shows them.
  std::vector<std::string> order;
  std::map<std::string, std::vector<const CLI::Option*>> groups;
  for (const CLI::Option* opt : cmd.get_options()) {
    if (opt->get_group().empty()) continue;
    const std::string group = opt->get_positional() ? "Positionals" : opt->get_group();
    if (!groups.count(group)) order.push_back(group);
    groups[group].push_back(opt);
  }
  for (const std::string& group : order) {
    out += "### " + cmd.get_name() + ": " + group + "\n\n| option | value (default) | what it does |\n|---|---|---|\n";
    for (const CLI::Option* opt : groups[group]) {
      std::string value = opt->get_type_name();
      if (!opt->get_default_str().empty()) value += (value.empty() ? "" : " ") + ("(" + opt->get_default_str() + ")");
      out += "| " + (opt->get_positional() ? "`" + opt->get_name() + "`" : Names(*opt)) + " | " + Cell(value) + " | " +
             Cell(opt->get_description()) + " |\n";
    }
    out += "\n";
  }
  return out;
}

}  // namespace

std::string CliReference(const CLI::App& app) {
  std::string out;
  for (const CLI::App* cmd : app.get_subcommands([](const CLI::App* c) { return !c->get_group().empty(); })) {
    out += Command(*cmd);
  }
  return out;
}

Subcommand AddCliReferenceCommand(CLI::App* app) {
  CLI::App* cmd = app->add_subcommand("cli-reference", "print docs/cli.md's option reference (Markdown)");
  cmd->group("");  // not listed in --help
  return {cmd, [app] {
            std::fputs(CliReference(*app).c_str(), stdout);
            return 0;
          }};
}

}  // namespace f2c::app
