#pragma once
/// \file
/// The robot programming languages robcal reads and writes, and how a file says which it is.

#include <optional>
#include <string>
#include <string_view>

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

/// The line that says which language a text is in: its header or block start.
struct LanguageMarker {
  ProgramLanguage language;
  int line = 0;        ///< 1-based
  std::string marker;  ///< as the language names it, e.g. "MODULE", "/PROG"
};

/// The first line of `text` that only one language starts a program with: RAPID `MODULE name`;
/// KRL `DEF name(...)` (no ':' after it), `DEFDAT name`, `DEFFCT` or an `&ACCESS`/`&REL`/`&PARAM`
/// directive; Fanuc LS `/PROG name`; Yaskawa `/JOB`; URScript `def name():`. Comment lines start
/// otherwise and never match. None: the text has no header (a fragment).
std::optional<LanguageMarker> recognise_program_language(std::string_view text);

/// InputError at the marker's line when `text` starts a program in another language than
/// `language` (a RAPID module renamed .src reads as a KRL file without points, and would be
/// "filtered" into a copy of itself): names the language the text looks like.
void require_program_language(std::string_view text, ProgramLanguage language,
                              const std::string& file);

}  // namespace robcal
