#include "robcal/io/journal_file.hpp"

#include <fmt/format.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <fstream>
#include <sstream>

#include "robcal/core/error.hpp"
#include "robcal/io/atomic_file.hpp"

namespace robcal {
namespace {

/// The process holding a flock on `file`, from /proc/locks (whose device is "major:minor" in
/// hex and whose inode is decimal), or 0 when it cannot be told.
long lock_holder(int fd) {
  struct stat st {};
  if (::fstat(fd, &st) != 0) return 0;
  std::ifstream locks("/proc/locks");
  std::string line;
  while (std::getline(locks, line)) {
    std::istringstream fields(line);
    std::string number, kind, mode, access, device;
    long pid = 0;
    if (!(fields >> number >> kind) || kind == "->" || kind != "FLOCK") continue;
    if (!(fields >> mode >> access >> pid >> device)) continue;
    unsigned major = 0, minor = 0;
    unsigned long long inode = 0;
    if (std::sscanf(device.c_str(), "%x:%x:%llu", &major, &minor, &inode) == 3 &&
        major == ::major(st.st_dev) && minor == ::minor(st.st_dev) && inode == st.st_ino)
      return pid;
  }
  return 0;
}

/// Takes the journal's exclusive lock, else closes `file` and refuses: two sessions writing
/// one journal would interleave their readings.
void lock_journal(const std::filesystem::path& path, std::FILE* file) {
  const int fd = ::fileno(file);
  if (::flock(fd, LOCK_EX | LOCK_NB) == 0) return;
  const long holder = lock_holder(fd);
  std::fclose(file);
  throw InputError(
      {path.string(), 0, 0, "--journal"},
      fmt::format("the journal is in use by another session ({}): finish or stop "
                  "that one first",
                  holder > 0 ? fmt::format("process {}", holder) : std::string("process unknown")));
}

}  // namespace

JournalFile JournalFile::create(const std::filesystem::path& path) {
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  std::FILE* file = std::fopen(path.c_str(), "wx");  // exclusive: never overwrite a session
  if (file == nullptr)
    throw InputError({path.string(), 0, 0, "--journal"},
                     std::filesystem::exists(path)
                         ? "the journal exists already: continue it with --resume or choose "
                           "another file"
                         : "cannot create the journal file");
  lock_journal(path, file);
  return JournalFile(path, file);
}

JournalFile JournalFile::open_for_resume(const std::filesystem::path& path) {
  if (!std::filesystem::exists(path))
    throw InputError({path.string(), 0, 0, "--journal"}, "no journal to resume");
  std::FILE* file = std::fopen(path.c_str(), "a+");
  if (file == nullptr)
    throw InputError({path.string(), 0, 0, "--journal"}, "cannot open the journal");
  lock_journal(path, file);
  return JournalFile(path, file);
}

JournalFile::JournalFile(std::filesystem::path path, std::FILE* file)
    : path_(std::move(path)), file_(file) {}

JournalFile::JournalFile(JournalFile&& other) noexcept
    : path_(std::move(other.path_)), file_(other.file_) {
  other.file_ = nullptr;
}

JournalFile::~JournalFile() {
  if (file_ != nullptr) std::fclose(file_);
}

std::string JournalFile::text() const {
  return read_text_file(path_);
}

void JournalFile::truncate(size_t bytes) {
  std::fflush(file_);
  std::filesystem::resize_file(path_, bytes);
}

void JournalFile::append_line(const std::string& line) {
  if (std::fputs(line.c_str(), file_) < 0 || std::fflush(file_) != 0 ||
      ::fsync(::fileno(file_)) != 0)
    throw InputError({path_.string(), 0, 0, "--journal"}, "cannot write to the journal");
}

}  // namespace robcal
