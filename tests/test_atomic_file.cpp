// The atomic writer: a new file or a regular file is replaced whole (permissions kept); a
// symbolic link is followed and stays a link; a FIFO is written into and stays a FIFO; a folder
// is refused. refuse_overwriting_inputs catches an output that is an input by any name.

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "refusal.hpp"
#include "robcal/core/error.hpp"
#include "robcal/io/atomic_file.hpp"

namespace robcal {
namespace {

namespace fs = std::filesystem;

/// A fresh folder for one test, removed at the end.
struct ScratchDir {
  fs::path path;
  explicit ScratchDir(const std::string& name)
      : path(fs::temp_directory_path() /
             ("robcal_atomic_" + name + "_" + std::to_string(::getpid()))) {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~ScratchDir() { fs::remove_all(path); }
};

std::string slurp(const fs::path& path) {
  std::ifstream in(path);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

TEST(AtomicFile, CreatesParentsAndReplacesRegularFileKeepingPermissions) {
  ScratchDir dir("regular");
  const fs::path out = dir.path / "sub" / "out.txt";
  write_file_atomically(out, "first");
  EXPECT_EQ(slurp(out), "first");
  fs::permissions(out, fs::perms::owner_read | fs::perms::owner_write);
  write_file_atomically(out, "second");
  EXPECT_EQ(slurp(out), "second");
  EXPECT_EQ(fs::status(out).permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write);
  // No temporary left beside it.
  EXPECT_EQ(std::distance(fs::directory_iterator(out.parent_path()), fs::directory_iterator{}), 1);
}

TEST(AtomicFile, SeveralFilesAllOrNothing) {
  ScratchDir dir("several");
  const fs::path first = dir.path / "first.json";
  const fs::path second = dir.path / "second.json";
  write_file_atomically(first, "old first");
  write_files_atomically({{first, "new first"}, {second, "new second"}});
  EXPECT_EQ(slurp(first), "new first");
  EXPECT_EQ(slurp(second), "new second");
  const auto entries = [&] {
    return std::distance(fs::directory_iterator(dir.path), fs::directory_iterator{});
  };
  EXPECT_EQ(entries(), 2);

  // The second target in a folder that cannot be made (a file stands where the folder would
  // be), or a folder itself: the first is left as it was, no temporary left anywhere.
  write_file_atomically(dir.path / "blocker", "a file");
  for (const fs::path& bad : {dir.path / "blocker" / "sub" / "second.json", dir.path}) {
    const std::string why = test::refusal_message([&] {
      write_files_atomically({{first, "newer first"}, {bad, "newer second"}});
    });
    EXPECT_NE(why.find(bad.string()), std::string::npos) << why;
    EXPECT_EQ(slurp(first), "new first");
    EXPECT_EQ(slurp(second), "new second");
    EXPECT_EQ(entries(), 3) << "a temporary left behind";
  }
  // A missing folder is created, as for one file.
  write_files_atomically({{first, "third"}, {dir.path / "new" / "x.json", "x"}});
  EXPECT_EQ(slurp(first), "third");
  EXPECT_EQ(slurp(dir.path / "new" / "x.json"), "x");
}

TEST(AtomicFile, FollowsSymbolicLinkAndKeepsIt) {
  ScratchDir dir("link");
  fs::create_directories(dir.path / "data");
  write_file_atomically(dir.path / "data" / "real.txt", "old");
  fs::create_symlink("data/real.txt", dir.path / "link.txt");
  write_file_atomically(dir.path / "link.txt", "new");
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(dir.path / "link.txt")));
  EXPECT_EQ(slurp(dir.path / "data" / "real.txt"), "new");
  // A dangling link: the file it names is created.
  fs::create_symlink("data/missing.txt", dir.path / "dangling.txt");
  write_file_atomically(dir.path / "dangling.txt", "made");
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(dir.path / "dangling.txt")));
  EXPECT_EQ(slurp(dir.path / "data" / "missing.txt"), "made");
}

TEST(AtomicFile, WritesIntoFifoWithoutReplacingIt) {
  ScratchDir dir("fifo");
  const fs::path fifo = dir.path / "pipe";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string received;
  std::thread reader([&] { received = slurp(fifo); });
  write_file_atomically(fifo, "through the pipe");
  reader.join();
  EXPECT_EQ(received, "through the pipe");
  EXPECT_TRUE(fs::is_fifo(fs::symlink_status(fifo)));
}

TEST(AtomicFile, RefusesFolder) {
  ScratchDir dir("folder");
  try {
    write_file_atomically(dir.path, "x");
    FAIL() << "a folder was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("is a directory"), std::string::npos) << e.what();
  }
}

TEST(AtomicFile, RefusesOutputThatIsAnInputByAnyName) {
  ScratchDir dir("inputs");
  const fs::path input = dir.path / "m.csv", other = dir.path / "other.csv";
  write_file_atomically(input, "data");
  write_file_atomically(other, "data");
  fs::create_symlink("m.csv", dir.path / "link.csv");
  fs::create_hard_link(input, dir.path / "hard.csv");
  const std::vector<fs::path> inputs = {"-", other, input};
  for (const fs::path& out : {input, dir.path / "link.csv", dir.path / "hard.csv",
                              dir.path / ".." / dir.path.filename() / "m.csv"}) {
    try {
      refuse_overwriting_inputs(out, inputs, "--tool-out");
      FAIL() << out << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("refusing to overwrite"), std::string::npos);
      EXPECT_EQ(e.where().key, "--tool-out");
    }
  }
  EXPECT_NO_THROW(refuse_overwriting_inputs(dir.path / "new.csv", inputs));
  EXPECT_NO_THROW(refuse_overwriting_inputs("-", inputs));
  EXPECT_NO_THROW(refuse_overwriting_inputs(dir.path / "x.csv", {dir.path / "y.csv"}));
}

TEST(AtomicFile, RefusesTwoOutputsOnOnePathButSharesDevices) {
  ScratchDir dir("shared");
  const fs::path model = dir.path / "m.yaml";
  EXPECT_EQ(test::refusal_message([&] {
              refuse_shared_outputs({{"--out", model},
                                     {"--legs-out", "x.csv"},
                                     {"--tool-out", dir.path / "s" / ".." / "m.yaml"}});
            }),
            "--tool-out: '" + (dir.path / "s" / ".." / "m.yaml").string() +
                "' is also the file of --out: each output needs a path of its own");
  EXPECT_NO_THROW(refuse_shared_outputs({{"--out", "-"}, {"--tool-out", "-"}}));
  EXPECT_NO_THROW(refuse_shared_outputs({{"--out", "/dev/null"}, {"--tool-out", "/dev/null"}}));
  EXPECT_NO_THROW(refuse_shared_outputs({{"--out", model}, {"--tool-out", dir.path / "t.yaml"}}));
}

TEST(AtomicFile, RefusesAFileWhereAFolderIsWritten) {
  ScratchDir dir("folder_out");
  write_file_atomically(dir.path / "file", "x");
  EXPECT_EQ(test::refusal_message([&] { refuse_non_folder(dir.path / "file", "--out"); }),
            (dir.path / "file").string() +
                " (--out): exists and is not a folder: expected a folder to write into, or a new "
                "path");
  EXPECT_NO_THROW(refuse_non_folder(dir.path));
  EXPECT_NO_THROW(refuse_non_folder(dir.path / "new"));
}

}  // namespace
}  // namespace robcal
