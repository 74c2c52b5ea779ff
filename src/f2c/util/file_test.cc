#include "f2c/util/file.h"

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <filesystem>
#include <thread>

#include "f2c/util/error.h"

namespace f2c {
namespace {
namespace fs = std::filesystem;

fs::path TempDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("f2c_file_test_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// A run that fails part-way: the folders it made and left empty go, its files and what was
// there before stay; a run that finishes keeps everything.
TEST(OutputFolder, AFailedRunLeavesOnlyItsFilesAndWhatWasThere) {
  const fs::path root = TempDir("output_folder");
  const fs::path fresh = root / "fresh";
  try {
    const OutputFolder folder(fresh);
    fs::create_directories(fresh / "cache" / "deeper");
    throw InputError("stopped");
  } catch (const InputError&) {
  }
  EXPECT_FALSE(fs::exists(fresh));

  const fs::path used = root / "used";
  fs::create_directories(used / "mine");  // empty, but the user's
  try {
    const OutputFolder folder(used);
    fs::create_directories(used / "cache");
    fs::create_directories(used / "iterations");
    WriteFileAtomic(used / "cache" / "odometry.bin", "done");
    throw InputError("stopped");
  } catch (const InputError&) {
  }
  EXPECT_TRUE(fs::is_directory(used / "mine"));
  EXPECT_EQ(ReadFileToString(used / "cache" / "odometry.bin"), "done");
  EXPECT_FALSE(fs::exists(used / "iterations"));

  const fs::path kept = root / "kept";
  {
    const OutputFolder folder(kept);
    fs::create_directories(kept / "cache");
  }
  EXPECT_TRUE(fs::is_directory(kept / "cache"));
}

// The caches on disk are keyed by these hashes: XXH3's published value for no bytes (so a
// library update that changed them would show here), and one changed byte changes the hash.
TEST(HashFile, IsXxh3OfTheBytes) {
  const fs::path dir = TempDir("hash");
  WriteFileAtomic(dir / "empty", "");
  EXPECT_EQ(HashFile(dir / "empty"), 0x2d06800538d394c2ULL);
  std::string bytes(1 << 20, 'x');
  WriteFileAtomic(dir / "a", bytes);
  bytes[777777] = 'y';
  WriteFileAtomic(dir / "b", bytes);
  WriteFileAtomic(dir / "c", bytes);
  EXPECT_NE(HashFile(dir / "a"), HashFile(dir / "b"));
  EXPECT_EQ(HashFile(dir / "b"), HashFile(dir / "c"));
  EXPECT_THROW(HashFile(dir / "missing"), InputError);
}

TEST(WriteFileAtomic, WritesContentAndLeavesNoTemporaryFile) {
  const fs::path dir = TempDir("atomic");
  WriteFileAtomic(dir / "a.txt", "hello\n");
  EXPECT_EQ(ReadFileToString(dir / "a.txt"), "hello\n");
  int files = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 1);
}

TEST(WriteFileAtomic, AFolderInPlaceOfTheFileIsRefusedAndLeavesNoTemporaryFile) {
  const fs::path dir = TempDir("atomic_fail");
  fs::create_directories(dir / "target" / "inside");
  try {
    WriteFileAtomic(dir / "target", "new");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), (dir / "target").string() + ": is a folder, not a file");
  }
  int files = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 1);  // just the folder: no temporary file
  EXPECT_TRUE(fs::is_directory(dir / "target" / "inside"));
}

// What is not a regular file is written through, never renamed over: /dev/null stays the
// device, a FIFO's reader gets the bytes, and a link keeps naming the file it names.
TEST(WriteFileAtomic, DevicesAndFifosAreWrittenThroughAndLinksKept) {
  const fs::path dir = TempDir("atomic_devices");
  WriteFileAtomic("/dev/null", "nothing\n");
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
  const fs::path fifo = dir / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string received;
  std::thread reader([&] { received = ReadFileToString(fifo); });
  WriteFileAtomic(fifo, "through the pipe\n");
  reader.join();
  EXPECT_EQ(received, "through the pipe\n");
  EXPECT_TRUE(fs::is_fifo(fifo));
  WriteFileAtomic(dir / "real.txt", "old");
  fs::create_symlink("real.txt", dir / "link.txt");
  WriteFileAtomic(dir / "link.txt", "new");
  EXPECT_TRUE(fs::is_symlink(dir / "link.txt"));
  EXPECT_EQ(ReadFileToString(dir / "real.txt"), "new");
  int files = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 3);  // fifo, real.txt, link.txt: no temporary file
}

// A device that refuses the bytes (a full disk) is an error naming it. /dev/full is only
// written through (never replaced: the test above), so the test may run as root.
TEST(WriteFileAtomic, AFullDeviceIsAnError) {
  if (!fs::is_character_file("/dev/full")) GTEST_SKIP() << "no /dev/full here";
  try {
    WriteFileAtomic("/dev/full", std::string(1 << 16, 'x'));
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "/dev/full: write failed (No space left on device)");
  }
  EXPECT_TRUE(fs::is_character_file("/dev/full"));
}

TEST(CheckCacheFile, AcceptsRegularOrAbsentAndNamesEverythingElse) {
  const fs::path dir = TempDir("cache_kind");
  CheckCacheFile(dir / "absent");
  WriteFileAtomic(dir / "file", "x");
  CheckCacheFile(dir / "file");
  ASSERT_EQ(::mkfifo((dir / "fifo").c_str(), 0600), 0);
  auto message = [](const fs::path& p) {
    try {
      CheckCacheFile(p);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message(dir / "fifo"),
            (dir / "fifo").string() + ": cache is not a regular file (a device, FIFO or socket)");
  EXPECT_EQ(message(dir), dir.string() + ": cache is a folder, not a file");
  fs::create_symlink("/dev/zero", dir / "zero");
  EXPECT_EQ(message(dir / "zero"),
            (dir / "zero").string() + ": cache is not a regular file (a device, FIFO or socket)");
}

TEST(WriteFileAtomic, MissingFolderNamesThePath) {
  const fs::path path = TempDir("missing") / "no" / "such" / "a.txt";
  try {
    WriteFileAtomic(path, "x");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(path.string() + ": cannot write", 0), 0u) << e.what();
  }
}

TEST(ReadFileToString, MissingFileMessage) {
  const fs::path path = TempDir("read") / "absent.txt";
  try {
    ReadFileToString(path);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), path.string() + ": no such file");
  }
}

TEST(EnsureWritableDirectory, RejectsAFileInPlaceOfAFolder) {
  const fs::path dir = TempDir("ensure");
  WriteFileAtomic(dir / "f", "x");
  try {
    EnsureWritableDirectory(dir / "f");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), (dir / "f").string() + ": exists and is not a folder");
  }
}

TEST(Fnv1a64, KnownVectors) {
  // Reference values of the 64-bit FNV-1a specification.
  EXPECT_EQ(Fnv1a64(""), 0xcbf29ce484222325ULL);
  EXPECT_EQ(Fnv1a64("a"), 0xaf63dc4c8601ec8cULL);
  EXPECT_EQ(Fnv1a64("foobar"), 0x85944171f73967e8ULL);
}

TEST(CacheDamage, SaysWhatWasFoundInOnePhrase) {
  EXPECT_EQ(CacheDamage(0, false), "");
  EXPECT_EQ(CacheDamage(1, false), "has 1 entry that fails its checksum");
  EXPECT_EQ(CacheDamage(3, true), "has 3 entries that fail their checksum and is cut short");
  EXPECT_EQ(CacheDamage(0, true), "is cut short");
}

}  // namespace
}  // namespace f2c
