#pragma once
/// \file
/// Output files are written whole or not at all: to a temporary file beside the target, then
/// renamed over it, so a crash or a bad input never leaves a partial file.

#include <filesystem>
#include <string_view>

namespace robcal {

/// Writes `content` to `path` atomically (temporary file + rename). Creates missing parent
/// directories. Throws InputError naming the path when it cannot be written.
void write_file_atomically(const std::filesystem::path& path, std::string_view content);

/// Reads a whole file; throws InputError naming the path when it cannot be read.
std::string read_text_file(const std::filesystem::path& path);

}  // namespace robcal
