#include "robcal/programs/program_language.hpp"

#include <algorithm>
#include <array>
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

const char* program_language_name(ProgramLanguage language) {
  return info(language).name;
}

const char* program_extension(ProgramLanguage language) {
  return info(language).extension;
}

}  // namespace robcal
