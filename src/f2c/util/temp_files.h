#pragma once
// Temporary files that a run writes before renaming them into place (a cache being
// streamed, an output written whole then renamed). A run stopped by a signal removes them
// before it dies, and a later run removes those of runs that no longer exist, so no
// `*.tmp.PID` file outlives its run.

#include <filesystem>
#include <string>

namespace f2c {

// Holds a temporary file's name for as long as it lives: while registered, SIGINT, SIGTERM,
// SIGHUP and SIGPIPE remove it (when InstallTemporaryFileCleanup was called). Destruction
// only forgets the name; the owner removes or renames the file.
class TemporaryFileName {
 public:
  explicit TemporaryFileName(const std::filesystem::path& path);
  ~TemporaryFileName();
  TemporaryFileName(const TemporaryFileName&) = delete;
  TemporaryFileName& operator=(const TemporaryFileName&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  int slot_ = -1;  // -1: more temporaries at once than the registry holds (then not removed by a signal)
};

// `path` + ".tmp.<pid>", the name every temporary of this process starts with.
std::string TemporaryName(const std::filesystem::path& path);

// Installs handlers for SIGINT, SIGTERM, SIGHUP and SIGPIPE that remove the registered
// temporaries, then let the signal end the process as it would have (its default action,
// so the exit status still says which signal). For programs, not libraries: the Python
// module leaves the interpreter's handlers alone.
void InstallTemporaryFileCleanup();

// Removes `*.tmp.<pid>` and `*.tmp.<pid>.<n>` files in `dir` and its subfolders whose process
// is gone (a run killed by SIGKILL or a power cut). Returns how many it removed.
int RemoveStaleTemporaries(const std::filesystem::path& dir);

}  // namespace f2c
