// fine2coarse: RGB-D sequence -> camera poses (and, as the pipeline grows, mesh and report).
//
//   fine2coarse register INPUT -o OUTDIR [options]
//   fine2coarse features INPUT -o OUTDIR [--images] [--ply]
//   fine2coarse fuse INPUT --trajectory FILE -o mesh.ply [--voxel-size M]
//   fine2coarse evaluate --estimate FILE --ground-truth FILE_OR_DATASET [--json]
//   fine2coarse simulate -o OUTDIR [--scene S] [--frames N]
//   fine2coarse demo [-o OUTDIR]
//   fine2coarse info INPUT
//
// Exit status: 0 success, 1 bad input or a failed write (one line naming the file), 2 bad
// usage; 3 only for a bug (a broken internal check). See main().

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <new>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <vector>

#include "apps/cli_reference.h"
#include "apps/commands.h"
#include "f2c/optim/blas_threads.h"
#include "f2c/util/error.h"
#include "f2c/util/temp_files.h"
#include "apps/config_check.h"

int main(int argc, char** argv) {
  // Logs go to stderr, so stdout carries only results (tables, JSON).
  spdlog::set_default_logger(spdlog::stderr_color_mt("fine2coarse"));
  spdlog::set_pattern("[%H:%M:%S] %v");
  f2c::UseOneBlasThread();             // before any stage: OpenBLAS's own threads compete with ours
  f2c::InstallTemporaryFileCleanup();  // Ctrl-C, kill or a closed pipe leave no *.tmp.PID file
  CLI::App app{"fine2coarse: fine-to-coarse global registration of RGB-D scans"};
  app.require_subcommand(1);
  app.set_version_flag("--version", F2C_VERSION);
  // `register --help` lists the options users set; `register --help-all` every one, grouped.
  app.set_help_all_flag("--help-all", "every option, grouped (--help: the ones users set)");
  // Runs reproducible from a file: options in TOML/INI, one section per subcommand
  // ([register]); an unknown key is an error, not a hint. register --write-config writes one.
  app.set_config("--config", "", "read options from a TOML/INI file ([register] section; --write-config writes one)");
  app.allow_config_extras(CLI::config_extras_mode::error);
  app.fallthrough();
  using namespace f2c::app;
  const std::vector<Subcommand> commands = {
      AddRegisterCommand(&app), AddFeaturesCommand(&app), AddEvaluateCommand(&app), AddSimulateCommand(&app),
      AddDemoCommand(&app),     AddInfoCommand(&app),     AddFuseCommand(&app),     AddCliReferenceCommand(&app)};
  // Results (and --help, --version) go to stdout: a full disk or a closed pipe must not pass
  // for success.
  auto stdout_failed = [] {
    std::cout.flush();
    if (std::fflush(stdout) == 0 && !std::ferror(stdout) && std::cout.good()) return false;
    std::fprintf(stderr, "error: stdout: %s\n", std::strerror(errno != 0 ? errno : EIO));
    return true;
  };
  // What CLI11 would read wrongly from a config file: a usage error, as its own are.
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    std::string file;
    if (arg == "--config" && i + 1 < argc) file = argv[i + 1];
    if (arg.rfind("--config=", 0) == 0) file = arg.substr(9);
    if (file.empty()) continue;
    try {
      CheckConfigFile(file);
    } catch (const f2c::InputError& e) {
      std::fprintf(stderr, "error: %s\n", e.what());
      return 2;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    const int code = app.exit(e);
    return stdout_failed() ? 1 : code;
  } catch (const CLI::CallForAllHelp& e) {
    const int code = app.exit(e);
    return stdout_failed() ? 1 : code;
  } catch (const CLI::CallForVersion& e) {
    const int code = app.exit(e);
    return stdout_failed() ? 1 : code;
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return 2;
  } catch (const f2c::InputError& e) {  // a value a flag cannot take (an unknown enum name)
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  // The contract, enforced here: whatever a user feeds in ends in exit 0, 1 (one line,
  // "error: <file>: <what>") or 2 (usage). A filesystem error names the path the system
  // refused; running out of memory says so; a library's exception is still one line and
  // exit 1. Only a broken invariant of our own (F2C_CHECK, a bug) exits 3.
  int code = 2;
  try {
    for (const Subcommand& command : commands) {
      if (command.cli->parsed()) {
        code = command.run();
        break;
      }
    }
  } catch (const f2c::InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  } catch (const std::filesystem::filesystem_error& e) {
    const std::string path = e.path1().empty() ? std::string("(empty path)") : e.path1().string();
    std::fprintf(stderr, "error: %s: %s\n", path.c_str(), e.code().message().c_str());
    return 1;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "error: out of memory (the input or an option asks for more than this machine has)\n");
    return 1;
  } catch (const f2c::InternalError& e) {
    std::fprintf(stderr, "internal error: %s (a bug: please report it with the command line)\n", e.what());
    return 3;
  } catch (const std::exception& e) {
    std::string what = e.what();
    std::replace(what.begin(), what.end(), '\n', ' ');
    std::fprintf(stderr, "error: %s\n", what.c_str());
    return 1;
  }
  return stdout_failed() ? 1 : code;
}
