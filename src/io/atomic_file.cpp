#include "robcal/io/atomic_file.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <atomic>
#include <fstream>
#include <iostream>
#include <sstream>
#include <system_error>

#include "robcal/core/error.hpp"

namespace robcal {

namespace fs = std::filesystem;

namespace {

InputError write_error(const fs::path& path, const std::string& what) {
  return InputError(SourceLocation{path.string(), 0, 0, ""}, what);
}

/// Where the content for a path goes: standard output or a device/pipe, written in place, or a
/// regular file (links followed) replaced by renaming a temporary file beside it.
struct Target {
  fs::path path;  ///< as given, for messages
  bool in_place = false;
  fs::path file;  ///< the file written into or replaced
  fs::file_status status;
};

Target resolve_target(const fs::path& path) {
  std::error_code ec;
  Target t{path, true, path, {}};
  // Standard output (also by a name such as /dev/stdout, whatever it is connected to) is
  // written through std::cout, which the CLI points at the data, not the report.
  if (path == "-" || fs::equivalent(path, "/dev/stdout", ec)) {
    t.file = "-";
    return t;
  }
  // What the path names in the end (the kernel follows every link).
  t.status = fs::status(path, ec);
  if (fs::is_directory(t.status)) throw write_error(path, "is a directory, not a file");
  // A device, pipe or terminal: written into, never replaced.
  if (fs::exists(t.status) && !fs::is_regular_file(t.status)) return t;
  // A link is followed to the file it names (which may not exist yet), so the rename replaces
  // that file, not the link.
  t.in_place = false;
  for (int hops = 0; fs::is_symlink(fs::symlink_status(t.file, ec)); ++hops) {
    const fs::path next = fs::read_symlink(t.file, ec);
    if (ec || hops == 40) throw write_error(path, "cannot resolve the symbolic link");
    t.file = next.is_absolute() ? next : t.file.parent_path() / next;
  }
  return t;
}

void write_in_place(const Target& t, std::string_view content) {
  const auto write = [&](std::ostream& out) {
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    out.flush();
    if (!out) throw write_error(t.path, "write failed");
  };
  if (t.file == "-") return write(std::cout);
  std::ofstream out(t.file, std::ios::binary);
  if (!out) throw write_error(t.path, "cannot open for writing");
  write(out);
}

/// The content in a new temporary file beside the target (missing folders created); its path.
fs::path write_temporary(const Target& t, std::string_view content) {
  std::error_code ec;
  if (t.file.has_parent_path()) fs::create_directories(t.file.parent_path(), ec);
  // Unique per process and call: two threads writing beside each other never share one.
  static std::atomic<unsigned> counter{0};
  fs::path tmp = t.file;
  tmp += fmt::format(".tmp-{}-{}", ::getpid(), counter++);
  std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
  if (!out) throw write_error(t.path, "cannot open for writing");
  out.write(content.data(), static_cast<std::streamsize>(content.size()));
  out.flush();
  if (!out) {
    out.close();
    fs::remove(tmp, ec);
    throw write_error(t.path, "write failed (disk full?)");
  }
  // A replaced file keeps its permissions.
  if (fs::is_regular_file(t.status)) fs::permissions(tmp, t.status.permissions(), ec);
  return tmp;
}

}  // namespace

void write_files_atomically(const std::vector<std::pair<fs::path, std::string_view>>& files) {
  std::vector<Target> targets;
  targets.reserve(files.size());
  for (const auto& file : files) targets.push_back(resolve_target(file.first));
  std::vector<fs::path> temporaries(files.size());
  const auto remove_temporaries = [&] {
    for (const fs::path& tmp : temporaries) {
      std::error_code ignored;
      if (!tmp.empty()) fs::remove(tmp, ignored);
    }
  };
  try {
    for (size_t i = 0; i < files.size(); ++i)
      if (!targets[i].in_place) temporaries[i] = write_temporary(targets[i], files[i].second);
    // What cannot be replaced is written once every temporary is in place.
    for (size_t i = 0; i < files.size(); ++i)
      if (targets[i].in_place) write_in_place(targets[i], files[i].second);
  } catch (...) {
    remove_temporaries();
    throw;
  }
  for (size_t i = 0; i < files.size(); ++i) {
    if (temporaries[i].empty()) continue;
    std::error_code ec;
    fs::rename(temporaries[i], targets[i].file, ec);
    if (ec) {
      remove_temporaries();
      throw write_error(targets[i].path, "cannot replace the file: " + ec.message());
    }
    temporaries[i].clear();
  }
}

void write_file_atomically(const fs::path& path, std::string_view content) {
  write_files_atomically({{path, content}});
}

std::string read_text_file(const fs::path& path) {
  std::ostringstream ss;
  if (path == "-") {
    ss << std::cin.rdbuf();
    return ss.str();
  }
  std::error_code ec;
  if (fs::is_directory(path, ec))
    throw InputError(SourceLocation{path.string(), 0, 0, ""}, "is a directory, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw InputError(SourceLocation{path.string(), 0, 0, ""},
                     "cannot open for reading (does it exist?)");
  ss << in.rdbuf();
  return ss.str();
}

void refuse_overwriting_inputs(const fs::path& out, const std::vector<fs::path>& inputs,
                               std::string_view flag) {
  if (out == "-") return;
  std::error_code ec;
  // A path through a folder that does not exist yet ("new/../in.csv") names no file now, but
  // names the input once the writer has created the folder: compared as resolved.
  const fs::path resolved = fs::weakly_canonical(out, ec);
  for (const fs::path& input : inputs) {
    if (input == "-") continue;
    const auto same = [&](const fs::path& path) {
      std::error_code e;
      return !path.empty() && fs::equivalent(path, input, e) && !e;
    };
    if (same(out) || same(resolved))
      throw InputError(
          SourceLocation{"", 0, 0, std::string(flag)},
          fmt::format("'{}' is the input file '{}': refusing to overwrite it; write the output "
                      "to another path",
                      out.string(), input.string()));
  }
}

void refuse_non_folder(const fs::path& dir, std::string_view flag) {
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    throw InputError(SourceLocation{dir.string(), 0, 0, std::string(flag)},
                     "exists and is not a folder: expected a folder to write into, or a new path");
}

void refuse_shared_outputs(
    const std::vector<std::pair<std::string, std::filesystem::path>>& outputs) {
  const auto shareable = [](const fs::path& path) {
    std::error_code ec;
    return path == "-" || (fs::exists(path, ec) && !fs::is_regular_file(path, ec));
  };
  const auto resolved = [](const fs::path& path) {
    std::error_code ec;
    return fs::weakly_canonical(fs::absolute(path, ec), ec);
  };
  for (size_t second = 1; second < outputs.size(); ++second) {
    const auto& [flag, path] = outputs[second];
    if (shareable(path)) continue;
    for (size_t first = 0; first < second; ++first)
      if (resolved(outputs[first].second) == resolved(path))
        throw InputError(
            SourceLocation{"", 0, 0, flag},
            fmt::format("'{}' is also the file of {}: each output needs a path of its own",
                        path.string(), outputs[first].first));
  }
}

}  // namespace robcal
