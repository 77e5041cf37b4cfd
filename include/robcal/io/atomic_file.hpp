#pragma once
/// \file
/// Output files are written whole or not at all: to a temporary file beside the target, then
/// renamed over it, so a crash or a bad input never leaves a partial file. The rename happens
/// only onto a regular file or a new path: a symbolic link is followed to the file it names
/// (the link stays), a device or pipe (/dev/stdout, /dev/null, a FIFO) is written into, never
/// replaced. "-" is standard output for writing and standard input for reading.

#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace robcal {

/// Writes `content` to `path` atomically (temporary file + rename, see above). Creates missing
/// parent directories. Throws InputError naming the path when it cannot be written.
void write_file_atomically(const std::filesystem::path& path, std::string_view content);

/// Writes several files all or nothing: every regular target to a temporary file beside it first
/// (then devices, pipes and standard output, written in place as above), and only when all are
/// written are the temporaries renamed over their targets. When a target cannot be written
/// (a folder, a folder that cannot be created, a full disk) the temporaries are removed and no
/// regular target is touched; throws InputError naming that path. (A rename refused after others
/// succeeded, which needs the folder to change under the writer, leaves those replaced.)
void write_files_atomically(
    const std::vector<std::pair<std::filesystem::path, std::string_view>>& files);

/// Reads a whole file ("-": standard input); throws InputError naming the path when it cannot
/// be read.
std::string read_text_file(const std::filesystem::path& path);

/// Throws InputError naming `flag` when `out` is, or resolves (links, "..", hard links) to,
/// one of `inputs`: writing it would destroy the data the output is computed from. "-" and
/// paths that do not exist yet never clash.
void refuse_overwriting_inputs(const std::filesystem::path& out,
                               const std::vector<std::filesystem::path>& inputs,
                               std::string_view flag = "--out");

/// Throws InputError naming `flag` when the output folder `dir` exists as something other than
/// a folder (a file given where a folder is written): checked before the work that fills it.
void refuse_non_folder(const std::filesystem::path& dir, std::string_view flag = "--out");

/// Throws InputError naming the second flag when two outputs of one command line (flag, path)
/// name the same file: the second would silently replace the first. "-" and devices
/// (/dev/null, /dev/stdout) may be shared.
void refuse_shared_outputs(
    const std::vector<std::pair<std::string, std::filesystem::path>>& outputs);

}  // namespace robcal
