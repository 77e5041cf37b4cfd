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

/// Writes into an existing non-regular file (device, pipe) or standard output, in place.
void write_in_place(std::ostream& out, const fs::path& path, std::string_view content) {
  out.write(content.data(), static_cast<std::streamsize>(content.size()));
  out.flush();
  if (!out) throw write_error(path, "write failed");
}

}  // namespace

void write_file_atomically(const fs::path& path, std::string_view content) {
  std::error_code ec;
  // Standard output (also by a name such as /dev/stdout, whatever it is connected to) is
  // written through std::cout, which the CLI points at the data, not the report.
  if (path == "-" || fs::equivalent(path, "/dev/stdout", ec))
    return write_in_place(std::cout, path, content);
  // What the path names in the end (the kernel follows every link).
  const fs::file_status status = fs::status(path, ec);
  if (fs::is_directory(status)) throw write_error(path, "is a directory, not a file");
  if (fs::exists(status) && !fs::is_regular_file(status)) {
    // A device, pipe or terminal: written into, never replaced.
    std::ofstream out(path, std::ios::binary);
    if (!out) throw write_error(path, "cannot open for writing");
    return write_in_place(out, path, content);
  }
  // A link is followed to the file it names (which may not exist yet), so the rename replaces
  // that file, not the link.
  fs::path target = path;
  for (int hops = 0; fs::is_symlink(fs::symlink_status(target, ec)); ++hops) {
    const fs::path next = fs::read_symlink(target, ec);
    if (ec || hops == 40) throw write_error(path, "cannot resolve the symbolic link");
    target = next.is_absolute() ? next : target.parent_path() / next;
  }
  if (target.has_parent_path()) fs::create_directories(target.parent_path(), ec);
  // Unique per process and call: two threads writing beside each other never share one.
  static std::atomic<unsigned> counter{0};
  fs::path tmp = target;
  tmp += fmt::format(".tmp-{}-{}", ::getpid(), counter++);
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw write_error(path, "cannot open for writing");
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    out.flush();
    if (!out) {
      out.close();
      fs::remove(tmp, ec);
      throw write_error(path, "write failed (disk full?)");
    }
  }
  // A replaced file keeps its permissions.
  if (fs::is_regular_file(status)) fs::permissions(tmp, status.permissions(), ec);
  fs::rename(tmp, target, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw write_error(path, "cannot replace the file: " + ec.message());
  }
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
