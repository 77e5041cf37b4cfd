#include "robcal/programs/program_language.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <filesystem>
#include <string_view>

#include "robcal/core/error.hpp"

namespace robcal {
namespace {

struct LanguageInfo {
  ProgramLanguage language;
  const char* name;
  const char* extension;                     ///< written
  std::array<std::string_view, 4> accepted;  ///< read (lower case; empty entries unused)
};

constexpr std::array<LanguageInfo, 5> kLanguages{{
    {ProgramLanguage::Rapid, "rapid", ".mod", {".mod", ".modx", ".prg", ".sys"}},
    {ProgramLanguage::Krl, "krl", ".src", {".src", ".dat", "", ""}},
    {ProgramLanguage::FanucLs, "ls", ".ls", {".ls", "", "", ""}},
    {ProgramLanguage::Jbi, "jbi", ".jbi", {".jbi", "", "", ""}},
    {ProgramLanguage::UrScript, "urscript", ".script", {".script", ".urscript", "", ""}},
}};

const LanguageInfo& info(ProgramLanguage language) {
  return kLanguages[static_cast<size_t>(language)];
}

}  // namespace

ProgramLanguage program_language_from_path(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const LanguageInfo& l : kLanguages)
    if (!ext.empty() && std::find(l.accepted.begin(), l.accepted.end(), ext) != l.accepted.end())
      return l.language;
  throw InputError(SourceLocation{path, 0, 0, ""},
                   "unknown program type: expected an ABB RAPID module (.mod, .modx, .prg, .sys), "
                   "a KUKA KRL file (.src, .dat), a Fanuc TP source (.ls), a Yaskawa job (.jbi) "
                   "or a URScript file (.script, .urscript)");
}

ProgramLanguage program_language_from_name(const std::string& name, const std::string& flag) {
  for (const LanguageInfo& l : kLanguages)
    if (name == l.name) return l.language;
  throw InputError(SourceLocation{"", 0, 0, flag},
                   "expected rapid, krl, ls, jbi or urscript, found '" + name + "'");
}

namespace {

/// Case-insensitive `prefix` at the start of `line`, followed by a blank (or the line's end when
/// `alone`).
bool starts_with_word(std::string_view line, std::string_view prefix, bool alone = false) {
  if (line.size() < prefix.size()) return false;
  for (size_t k = 0; k < prefix.size(); ++k)
    if (std::toupper(static_cast<unsigned char>(line[k])) != prefix[k]) return false;
  if (line.size() == prefix.size()) return alone;
  return line[prefix.size()] == ' ' || line[prefix.size()] == '\t';
}

std::optional<LanguageMarker> marker_of(std::string_view line, int number) {
  const auto make = [&](ProgramLanguage l, const char* m) {
    return LanguageMarker{l, number, std::string(m)};
  };
  if (starts_with_word(line, "MODULE")) return make(ProgramLanguage::Rapid, "MODULE");
  if (starts_with_word(line, "/PROG")) return make(ProgramLanguage::FanucLs, "/PROG");
  if (starts_with_word(line, "/JOB", true)) return make(ProgramLanguage::Jbi, "/JOB");
  if (starts_with_word(line, "DEFDAT")) return make(ProgramLanguage::Krl, "DEFDAT");
  if (starts_with_word(line, "DEFFCT")) return make(ProgramLanguage::Krl, "DEFFCT");
  for (const char* directive : {"&ACCESS", "&REL", "&PARAM"})
    if (starts_with_word(line, directive)) return make(ProgramLanguage::Krl, directive);
  if (starts_with_word(line, "DEF") && line.find('(') != std::string_view::npos) {
    // URScript `def name():` ends with a colon (case-sensitive `def`); KRL `DEF name( )` not.
    std::string_view rest = line.substr(0, line.find_last_not_of(" \t") + 1);
    if (line.starts_with("def ") && rest.ends_with(":"))
      return make(ProgramLanguage::UrScript, "def name():");
    return make(ProgramLanguage::Krl, "DEF");
  }
  return std::nullopt;
}

}  // namespace

std::optional<LanguageMarker> recognise_program_language(std::string_view text) {
  int number = 0;
  for (size_t at = 0; at < text.size();) {
    ++number;
    size_t end = text.find('\n', at);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(at, end - at);
    at = end + 1;
    if (line.ends_with('\r')) line.remove_suffix(1);
    const size_t first = line.find_first_not_of(" \t\r\xEF\xBB\xBF");  // blanks and a BOM
    if (first == std::string_view::npos) continue;
    line.remove_prefix(first);
    if (auto marker = marker_of(line, number)) return marker;
  }
  return std::nullopt;
}

void require_program_language(std::string_view text, ProgramLanguage language,
                              const std::string& file) {
  static constexpr const char* kDescriptions[] = {"an ABB RAPID module", "a KUKA KRL program",
                                                  "a Fanuc LS program", "a Yaskawa JBI job",
                                                  "a URScript program"};
  const auto marker = recognise_program_language(text);
  if (!marker || marker->language == language) return;
  throw InputError(SourceLocation{file, marker->line, 1, ""},
                   fmt::format("'{}' here begins {}, not {} (the language of the file's name or "
                               "--lang): nothing corrected; give the file its own extension ({})",
                               marker->marker, kDescriptions[static_cast<size_t>(marker->language)],
                               kDescriptions[static_cast<size_t>(language)],
                               program_extension(marker->language)));
}

const char* program_language_name(ProgramLanguage language) {
  return info(language).name;
}

const char* program_extension(ProgramLanguage language) {
  return info(language).extension;
}

}  // namespace robcal
