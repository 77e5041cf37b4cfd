// The session journal file shared by the hexapod and the tracker/CMM sessions: exclusive
// create, resume, append, a torn last line cut, and the lock refusing a second writer.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>

#include "robcal/core/error.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/journal_file.hpp"

namespace robcal {
namespace {

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "no InputError";
}

TEST(JournalFile, CreateAppendResumeCutAndLock) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "robcal-journal-test";
  std::filesystem::remove_all(dir);
  const std::filesystem::path path = dir / "sub" / "j.txt";
  EXPECT_NE(
      message_of([&] { (void)JournalFile::open_for_resume(path); }).find("no journal to resume"),
      std::string::npos);
  {
    JournalFile journal = JournalFile::create(path);
    journal.append_line("a,1\n");
    journal.append_line("b,2\n");
    // Synced: another reader sees both lines at once.
    EXPECT_EQ(read_text_file(path), "a,1\nb,2\n");
    // A second writer, even in this process, is refused while the first holds the journal.
    const std::string held = message_of([&] { (void)JournalFile::open_for_resume(path); });
    EXPECT_NE(held.find("the journal is in use by another session (process "), std::string::npos)
        << held;
    EXPECT_NE(message_of([&] { (void)JournalFile::create(path); }).find("exists already"),
              std::string::npos);
  }
  // A crash mid-line: resume cuts the torn line and appends after the complete ones.
  std::ofstream(path, std::ios::app) << "c,3";
  JournalFile resumed = JournalFile::open_for_resume(path);
  EXPECT_EQ(resumed.text(), "a,1\nb,2\nc,3");
  resumed.truncate(8);
  resumed.append_line("c,4\n");
  EXPECT_EQ(resumed.text(), "a,1\nb,2\nc,4\n");
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace robcal
