#pragma once
/// \file
/// The append-only journal of a guided session (the hexapod session and the tracker/CMM
/// session): created exclusively (a session is never overwritten) or reopened to resume,
/// locked against a second writer for as long as it is open (flock: the kernel drops the lock
/// when the process ends, even by SIGKILL), every line flushed and synced to the disk before
/// append_line returns, and a last line cut short by a crash removed on resume. The line format
/// is the session's own.

#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <string>

namespace robcal {

class JournalFile {
 public:
  /// A new journal. \throws InputError (key --journal) naming the path when the file exists
  /// ("the journal exists already") or cannot be created, or another process holds it.
  static JournalFile create(const std::filesystem::path& path);
  /// An existing journal, to append to. \throws InputError (key --journal) when it does not
  /// exist ("no journal to resume"), cannot be opened or another process holds it.
  static JournalFile open_for_resume(const std::filesystem::path& path);

  /// The journal's text as it is on the disk.
  [[nodiscard]] std::string text() const;
  /// Cuts the file to its first `bytes` bytes (the complete lines, when the last one was torn
  /// by a crash: its reading was never confirmed to the operator).
  void truncate(size_t bytes);
  /// Appends `line` (ending in a newline) and syncs it to the disk before returning.
  /// \throws InputError (key --journal) when it cannot be written.
  void append_line(const std::string& line);

  [[nodiscard]] const std::filesystem::path& path() const { return path_; }

  JournalFile(JournalFile&& other) noexcept;
  JournalFile& operator=(JournalFile&&) = delete;
  ~JournalFile();

 private:
  JournalFile(std::filesystem::path path, std::FILE* file);
  std::filesystem::path path_;
  std::FILE* file_ = nullptr;
};

}  // namespace robcal
