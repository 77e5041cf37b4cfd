#pragma once
/// \file
/// The robot programming languages robcal reads and writes, and how a file says which it is.

#include <string>

namespace robcal {

enum class ProgramLanguage {
  Rapid,     ///< ABB RAPID module (.mod, .modx, .prg, .sys)
  Krl,       ///< KUKA KRL (.src, .dat)
  FanucLs,   ///< Fanuc TP source (.ls)
  Jbi,       ///< Yaskawa INFORM job (.jbi)
  UrScript,  ///< Universal Robots URScript (.script, .urscript)
};

/// The language from a file name's extension; InputError naming the file otherwise.
ProgramLanguage program_language_from_path(const std::string& path);

/// The language from its command-line name: rapid, krl, ls, jbi, urscript; InputError (key
/// `flag`) otherwise.
ProgramLanguage program_language_from_name(const std::string& name, const std::string& flag);

/// The command-line name (rapid, krl, ls, jbi, urscript).
const char* program_language_name(ProgramLanguage language);

/// The extension written for a program in `language` (".mod", ".src", ".ls", ".jbi",
/// ".script").
const char* program_extension(ProgramLanguage language);

}  // namespace robcal
